"""Statistics built on runs: covariance propagation, error budgets, Monte Carlo.

The simulation itself (trajectories, integrators, compiled loops, direct/linear/refined
runs, comparison) lives in :mod:`ins_errors.numeric`; this package only consumes it.
"""
