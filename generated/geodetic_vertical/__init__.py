# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/geodetic_vertical.py.
# Edit the model definition and run `make derive` again.
"""Generated metadata of the model 'geodetic_vertical': Inertial vertical on the spheroid, geodetic orthodromic coordinates."""

NAME = 'geodetic_vertical'
TITLE = 'Inertial vertical on the spheroid, geodetic orthodromic coordinates'
SOURCE = "004: Artyukhovsky & Studenikin, 'On one methodological error of the inertial vertical'"
STATES = (
    {'name': 'Phi', 'unit': 'rad', 'description': 'geodetic orthodromic latitude Φ (5)', 'latex': '\\Phi'},
    {'name': 'Lam', 'unit': 'rad', 'description': 'geodetic orthodromic longitude Λ (5)', 'latex': '\\Lambda'},
    {'name': 'W_xi', 'unit': 'm/s', 'description': 'relative velocity along ξ (along the orthodrome)', 'latex': 'W_\\xi'},
    {'name': 'W_eta', 'unit': 'm/s', 'description': 'relative velocity along η (orthodromic meridian)', 'latex': 'W_\\eta'},
)
ERROR_STATES = (
    {'name': 'delta_Phi', 'unit': 'rad', 'description': 'error of the computed geodetic orthodromic latitude Φ (5)', 'latex': '\\Delta \\Phi'},
    {'name': 'delta_Lam', 'unit': 'rad', 'description': 'error of the computed geodetic orthodromic longitude Λ (5)', 'latex': '\\Delta \\Lambda'},
    {'name': 'delta_W_xi', 'unit': 'm/s', 'description': 'error of the computed relative velocity along ξ (along the orthodrome)', 'latex': '\\Delta W_\\xi'},
    {'name': 'delta_W_eta', 'unit': 'm/s', 'description': 'error of the computed relative velocity along η (orthodromic meridian)', 'latex': '\\Delta W_\\eta'},
    {'name': 'alpha_x', 'unit': 'rad', 'description': 'platform misalignment about ξ', 'latex': '\\alpha_x'},
    {'name': 'alpha_y', 'unit': 'rad', 'description': 'platform misalignment about η', 'latex': '\\alpha_y'},
    {'name': 'alpha_z', 'unit': 'rad', 'description': 'platform misalignment in azimuth', 'latex': '\\alpha_z'},
)
INPUTS = (
    {'name': 'a_xi', 'unit': 'm/s**2', 'description': 'true apparent acceleration j_ξ along ξ', 'latex': 'j_\\xi'},
    {'name': 'a_eta', 'unit': 'm/s**2', 'description': 'true apparent acceleration j_η along η', 'latex': 'j_\\eta'},
    {'name': 'a_zeta', 'unit': 'm/s**2', 'description': 'true apparent acceleration j_ζ along the normal (≈ g)', 'latex': 'j_\\zeta'},
    {'name': 'V_zeta', 'unit': 'm/s', 'description': 'vertical velocity V_ζ (given from outside)', 'latex': 'V_\\zeta'},
)
PARAMETERS = (
    {'name': 'a', 'unit': 'm', 'description': 'semi-major axis of the ellipsoid', 'latex': 'a', 'default': 6378245.0},
    {'name': 'e2', 'unit': '1', 'description': 'first eccentricity squared (c = e²/(2 − e²))', 'latex': 'e^{2}', 'default': 0.006693421622965943},
    {'name': 'U', 'unit': 'rad/s', 'description': 'Earth rotation rate ω', 'latex': '\\omega', 'default': 7.292115e-05},
    {'name': 'orth_latitude', 'unit': 'rad', 'description': "geocentric latitude φ0 of the orthodrome's start point", 'latex': '\\varphi_0', 'default': 0.0},
    {'name': 'orth_longitude', 'unit': 'rad', 'description': "longitude λ0 of the orthodrome's start point", 'latex': '\\lambda_0', 'default': 0.0},
    {'name': 'orth_angle', 'unit': 'rad', 'description': 'orthodrome angle N0 at the start point', 'latex': 'N_0', 'default': 0.0},
)
SOURCES = (
    {'name': 'initial_tilt_x', 'unit': 'rad', 'description': 'initial platform misalignment about ξ', 'latex': '\\alpha_{x0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_tilt_y', 'unit': 'rad', 'description': 'initial platform misalignment about η', 'latex': '\\alpha_{y0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_azimuth_error', 'unit': 'rad', 'description': 'initial platform azimuth misalignment', 'latex': '\\alpha_{z0}', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'initial_velocity_error_xi', 'unit': 'm/s', 'description': 'error of the initial velocity W_ξ', 'latex': '\\Delta W_{\\xi 0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_velocity_error_eta', 'unit': 'm/s', 'description': 'error of the initial velocity W_η', 'latex': '\\Delta W_{\\eta 0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_Phi_error', 'unit': 'rad', 'description': 'error of the initial orthodromic latitude', 'latex': '\\Delta\\Phi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'initial_Lam_error', 'unit': 'rad', 'description': 'error of the initial orthodromic longitude', 'latex': '\\Delta\\Lambda_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'gyro_drift_x', 'unit': 'rad/s', 'description': 'constant drift of the gyro about ξ', 'latex': '\\omega_{dx}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_drift_y', 'unit': 'rad/s', 'description': 'constant drift of the gyro about η', 'latex': '\\omega_{dy}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_drift_z', 'unit': 'rad/s', 'description': 'constant drift of the azimuth gyro', 'latex': '\\omega_{dz}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'accel_bias_x', 'unit': 'm/s**2', 'description': 'zero offset of the ξ accelerometer', 'latex': '\\Delta j_\\xi', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'accel_bias_y', 'unit': 'm/s**2', 'description': 'zero offset of the η accelerometer', 'latex': '\\Delta j_\\eta', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
)
OUTPUTS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'geodetic latitude B', 'latex': 'B'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'longitude L', 'latex': 'L'},
    {'name': 'orthodrome_angle', 'unit': 'rad', 'description': 'orthodrome angle N', 'latex': 'N'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north relative velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east relative velocity', 'latex': 'v_E'},
)
INITIAL_CONDITIONS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'initial geodetic latitude B0', 'latex': 'B_0'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'initial longitude L0', 'latex': 'L_0'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'initial north relative velocity', 'latex': 'v_{N0}'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'initial east relative velocity', 'latex': 'v_{E0}'},
)
DOMAIN = ('orthodromic latitude at ±90°: Λ̇ divides by cos Φ', 'latitude at ±90° (|m32| = 1): the orthodrome angle N is undefined', 'a <= 0: the semi-major axis (Earth radius) must be positive', 'eccentricity squared must be below 1')
INITIAL_DOMAIN = ('initial latitude at ±90°: N is undefined at a pole', 'a <= 0: the semi-major axis (Earth radius) must be positive', 'eccentricity squared must be below 1')
MODE_NOTES = {'Earth': "not 2π/Ω on the ellipsoid, and not a slip of this code: the correction rates (9) keep the deflection terms (W_ξ/R) tg Φ ν2, −(W_ξ/R) tg Φ ν1 and −(W_η/R) ν2, which the dead reckoning Φ̇ = −W_η/R, Λ̇ = W_ξ/(R cos Φ) lacks, so a velocity error turns the platform and the trihedron of the reckoned (Φ, Λ) at different rates, and the platform's error against that trihedron no longer just turns with the Earth: ω ≈ Ω √(1 + μ (tg Φ cos N sin² B + sin² N sin B cos B)); on the default orthodrome (the meridian: N = 0, Φ = B) the period is shorter by ≈ c sin⁴ B (0.084 % at 45°, 0.316 % at 80°); exactly 2π/Ω with e2 = 0", 'Schuler': 'the north channel runs on R = a(1 − c sin² B) of (9), not on a radius of curvature, and the east channel, through −(W_ξ/R) tg Φ ν1 in Ω_η, on R/(1 − ν1 tg Φ); on the default orthodrome (the meridian) the pair is the textbook one for the geometric mean of the two, ≈ a, rather than √(R_M R_N) (−0.17 % at 80°); exactly the textbook periods with e2 = 0'}
MODEL_SOURCES_SHA256 = {'models/earth.py': 'ec12172d15c9a23221629c8217666a77c616a9c978ffb43a00af68784a7c9080', 'models/geodetic_vertical.py': '7a6218fcda627776077047fa2398f435a9a93edd9f5281d778a4f637bcdea687', 'models/platform.py': '6f1f24a68be4ffd6d6670dc25bc5ca00c17bf15301f383408ccd71ad16455f63'}
