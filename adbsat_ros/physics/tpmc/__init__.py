"""Test-particle Monte Carlo: the panel method's problem with every reflection followed.

Modules:

- ``inflow``: molecules entering a box around the body from a drifting Maxwellian, sampled
  exactly, and the closed-form fluxes through its faces;
- ``kernels``: re-emission from a surface (diffuse with energy accommodation, Maxwell,
  Cercignani-Lampis-Lord);
- ``tracing``: molecules followed through the panels until they leave, the momentum each gives;
- ``batches``: one flow about one body as a picklable problem, a batch's sums, worker processes;
- ``results``: :class:`TpmcCoefficients`, coefficients with standard errors;
- ``method``: :class:`TestParticleMethod`, the solver beside the panel method.
"""
