"""Figures on Agg-canvas Figures, never through pyplot: ``make_*_figure`` a Figure, ``plot_*`` PNGs.

- :mod:`.coefficients`: a database's coefficients against angle of attack.
- :mod:`.panels`: the mesh coloured by panel pressure coefficient.
- :mod:`.time_series`: force, torque, density, C_D against time; :mod:`.envelope` its summary.
- :mod:`.figures`: the Agg canvas.
"""
