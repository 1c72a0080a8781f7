"""Test-particle Monte Carlo: the panel method's problem with every reflection followed.

The method, its formulas and checks: docs/physics.md, section 12. Modules:

- ``inflow``: molecules entering a box around the body from a drifting Maxwellian;
- ``kernels``: re-emission from a surface (diffuse, Maxwell, Cercignani-Lampis-Lord);
- ``tracing``: molecules followed through the panels until they leave;
- ``batches``: one flow about one body as a picklable problem, a batch's sums, worker processes;
- ``results``: :class:`TpmcCoefficients`, coefficients with standard errors;
- ``method``: :class:`TestParticleMethod`, the solver beside the panel method.
"""
