"""psi_model.py as the 15-state model most filters carry: the six biases as states.

The state is z = (ψ, δv, δr, b_g, b_a): the ψ-angle model's nine states and the gyro and
accelerometer biases. The biases are random constants, so their rows are zero, and their
columns hold what G holds for them in the 9-state form:

    ż = [[F, G], [0, 0]] z

The bias names are the model's error sources (``ins-errors models strapdown_ned``). This
file is checked by

    ins-errors check strapdown_ned --matrix examples/strapdown/psi_model_15.py:psi_model_15 \
        --convention psi
"""

import numpy as np
import psi_model as textbook

# ψ, δv, δr, then the gyro and accelerometer biases (no SOURCES: this F has no G)
STATES = [*textbook.STATES, *textbook.SOURCES]


def psi_model_15(nav, imu):
    """F (15 × 15) of the ψ-angle model with gyro and accelerometer bias states."""
    F9, G = textbook.psi_model(nav, imu)
    F = np.zeros((15, 15))
    F[:9, :9] = F9
    F[:9, 9:] = G
    return F
