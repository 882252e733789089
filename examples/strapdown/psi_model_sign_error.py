"""psi_model.py with one deliberate mistake, for the example of a mistake being found.

The east entry of the gravity term Γ is written with the wrong sign, +g/R instead of
−g/R: the east channel then has no Schuler restoring force.
"""

from psi_model import SOURCES, STATES, psi_model  # noqa: F401  (the checker reads them)


def psi_model_sign_error(nav, imu):
    """The textbook ψ-angle model with F[dvc_E, dr_E] of the wrong sign."""
    F, G = psi_model(nav, imu)
    F[4, 7] = -F[4, 7]
    return F, G
