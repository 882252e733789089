# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/orthodromic.py.
# Edit the model definition and run `make derive` again.
"""Generated metadata of the model 'orthodromic': Orthodromic gyro-stabilised-platform INS."""

NAME = 'orthodromic'
TITLE = 'Orthodromic gyro-stabilised-platform INS'
SOURCE = "000: KPI lab manual 'Study of the algorithm and errors of an INS' (2010)"
STATES = (
    {'name': 'u11', 'unit': '1', 'description': 'direction cosine 11 (trihedron axis ξ on Greenwich axis 1)', 'latex': 'u_{11}'},
    {'name': 'u21', 'unit': '1', 'description': 'direction cosine 21 (trihedron axis η on Greenwich axis 1)', 'latex': 'u_{21}'},
    {'name': 'u31', 'unit': '1', 'description': 'direction cosine 31 (trihedron axis ζ on Greenwich axis 1)', 'latex': 'u_{31}'},
    {'name': 'u12', 'unit': '1', 'description': 'direction cosine 12 (trihedron axis ξ on Greenwich axis 2)', 'latex': 'u_{12}'},
    {'name': 'u22', 'unit': '1', 'description': 'direction cosine 22 (trihedron axis η on Greenwich axis 2)', 'latex': 'u_{22}'},
    {'name': 'u32', 'unit': '1', 'description': 'direction cosine 32 (trihedron axis ζ on Greenwich axis 2)', 'latex': 'u_{32}'},
    {'name': 'V_xi', 'unit': 'm/s', 'description': 'absolute horizontal velocity along ξ (along the great circle, at track angle χ from north)', 'latex': 'V_\\xi'},
    {'name': 'V_eta', 'unit': 'm/s', 'description': 'absolute horizontal velocity along η (to the left of ξ: west at χ = 0)', 'latex': 'V_\\eta'},
)
ERROR_STATES = (
    {'name': 'delta_u11', 'unit': '1', 'description': 'error of the computed direction cosine 11 (trihedron axis ξ on Greenwich axis 1)', 'latex': '\\Delta u_{11}'},
    {'name': 'delta_u21', 'unit': '1', 'description': 'error of the computed direction cosine 21 (trihedron axis η on Greenwich axis 1)', 'latex': '\\Delta u_{21}'},
    {'name': 'delta_u31', 'unit': '1', 'description': 'error of the computed direction cosine 31 (trihedron axis ζ on Greenwich axis 1)', 'latex': '\\Delta u_{31}'},
    {'name': 'delta_u12', 'unit': '1', 'description': 'error of the computed direction cosine 12 (trihedron axis ξ on Greenwich axis 2)', 'latex': '\\Delta u_{12}'},
    {'name': 'delta_u22', 'unit': '1', 'description': 'error of the computed direction cosine 22 (trihedron axis η on Greenwich axis 2)', 'latex': '\\Delta u_{22}'},
    {'name': 'delta_u32', 'unit': '1', 'description': 'error of the computed direction cosine 32 (trihedron axis ζ on Greenwich axis 2)', 'latex': '\\Delta u_{32}'},
    {'name': 'delta_V_xi', 'unit': 'm/s', 'description': 'error of the computed absolute horizontal velocity along ξ (along the great circle, at track angle χ from north)', 'latex': '\\Delta V_\\xi'},
    {'name': 'delta_V_eta', 'unit': 'm/s', 'description': 'error of the computed absolute horizontal velocity along η (to the left of ξ: west at χ = 0)', 'latex': '\\Delta V_\\eta'},
    {'name': 'alpha_x', 'unit': 'rad', 'description': 'platform misalignment about x (≈ξ)', 'latex': '\\alpha_x'},
    {'name': 'alpha_y', 'unit': 'rad', 'description': 'platform misalignment about y (≈η, to the left of ξ)', 'latex': '\\alpha_y'},
    {'name': 'alpha_z', 'unit': 'rad', 'description': 'platform misalignment about z (azimuth) from the computed orthodromic trihedron; from north: alpha_z + delta_heading', 'latex': '\\alpha_z'},
)
INPUTS = (
    {'name': 'a_xi', 'unit': 'm/s**2', 'description': 'true apparent acceleration along ξ', 'latex': 'a_\\xi'},
    {'name': 'a_eta', 'unit': 'm/s**2', 'description': 'true apparent acceleration along η', 'latex': 'a_\\eta'},
    {'name': 'a_zeta', 'unit': 'm/s**2', 'description': 'true apparent acceleration along ζ (≈ +g at rest)', 'latex': 'a_\\zeta'},
    {'name': 'V_zeta', 'unit': 'm/s', 'description': 'vertical velocity (given from outside)', 'latex': 'V_\\zeta'},
    {'name': 'h', 'unit': 'm', 'description': 'height above the ellipsoid (given from outside)', 'latex': 'h'},
)
PARAMETERS = (
    {'name': 'a', 'unit': 'm', 'description': 'semi-major axis of the ellipsoid', 'latex': 'a', 'default': 6378245.0},
    {'name': 'e2', 'unit': '1', 'description': 'first eccentricity squared of the ellipsoid', 'latex': 'e^{2}', 'default': 0.006693421622965943},
    {'name': 'U', 'unit': 'rad/s', 'description': 'Earth rotation rate', 'latex': 'U', 'default': 7.292115e-05},
)
SOURCES = (
    {'name': 'initial_tilt_x', 'unit': 'rad', 'description': 'initial platform levelling error about x', 'latex': '\\alpha_{x0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': 1},
    {'name': 'initial_tilt_y', 'unit': 'rad', 'description': 'initial platform levelling error about y', 'latex': '\\alpha_{y0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': 1},
    {'name': 'initial_azimuth_error', 'unit': 'rad', 'description': 'initial platform azimuth alignment error', 'latex': '\\alpha_{z0}', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 2},
    {'name': 'initial_velocity_error_xi', 'unit': 'm/s', 'description': 'error of the initial computed velocity along ξ', 'latex': '\\Delta V_{\\xi 0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': 3},
    {'name': 'initial_velocity_error_eta', 'unit': 'm/s', 'description': 'error of the initial computed velocity along η', 'latex': '\\Delta V_{\\eta 0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': 3},
    {'name': 'initial_latitude_error', 'unit': 'rad', 'description': 'error of the initial latitude set into the computer', 'latex': '\\Delta\\varphi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 4},
    {'name': 'initial_longitude_error', 'unit': 'rad', 'description': 'error of the initial longitude set into the computer', 'latex': '\\Delta\\lambda_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 4},
    {'name': 'initial_heading_error', 'unit': 'rad', 'description': 'error of the initial track angle of the computed trihedron', 'latex': '\\Delta\\chi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'gyro_drift_x', 'unit': 'rad/s', 'description': 'constant drift rate of the gyro about platform axis x', 'latex': '\\omega_{dx}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 5},
    {'name': 'gyro_drift_y', 'unit': 'rad/s', 'description': 'constant drift rate of the gyro about platform axis y', 'latex': '\\omega_{dy}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 5},
    {'name': 'gyro_drift_z', 'unit': 'rad/s', 'description': 'constant drift rate of the azimuth gyro', 'latex': '\\omega_{dz}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 6},
    {'name': 'accel_bias_x', 'unit': 'm/s**2', 'description': 'zero offset of the x accelerometer', 'latex': '\\Delta a_x', 'kind': 'constant', 'display_unit': 'ug', 'factor': 7},
    {'name': 'accel_bias_y', 'unit': 'm/s**2', 'description': 'zero offset of the y accelerometer', 'latex': '\\Delta a_y', 'kind': 'constant', 'display_unit': 'ug', 'factor': 7},
    {'name': 'velocity_integrator_offset_xi', 'unit': 'm/s**2', 'description': 'zero offset of the first (velocity) integrator, ξ channel, at its input', 'latex': '\\delta_{1\\xi}', 'kind': 'constant', 'display_unit': 'ug', 'factor': 8},
    {'name': 'velocity_integrator_offset_eta', 'unit': 'm/s**2', 'description': 'zero offset of the first (velocity) integrator, η channel, at its input', 'latex': '\\delta_{1\\eta}', 'kind': 'constant', 'display_unit': 'ug', 'factor': 8},
    {'name': 'position_integrator_offset_xi', 'unit': 'rad/s', 'description': "zero offset of the second integrator: rate added to ω'_ξ in the Poisson equations", 'latex': '\\delta_{2\\xi}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 9},
    {'name': 'position_integrator_offset_eta', 'unit': 'rad/s', 'description': "zero offset of the second integrator: rate added to ω'_η in the Poisson equations", 'latex': '\\delta_{2\\eta}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 9},
    {'name': 'accel_scale_error_x', 'unit': '1', 'description': 'scale-factor (transfer coefficient) error of the x accelerometer', 'latex': 'k_{ax}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 10},
    {'name': 'accel_scale_error_y', 'unit': '1', 'description': 'scale-factor (transfer coefficient) error of the y accelerometer', 'latex': 'k_{ay}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 10},
    {'name': 'velocity_integrator_gain_error_xi', 'unit': '1', 'description': 'gain error of the first (velocity) integrator, ξ channel', 'latex': 'k_{1\\xi}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 11},
    {'name': 'velocity_integrator_gain_error_eta', 'unit': '1', 'description': 'gain error of the first (velocity) integrator, η channel', 'latex': 'k_{1\\eta}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 11},
    {'name': 'position_integrator_gain_error_xi', 'unit': '1', 'description': "gain error of the second integrator on ω'_ξ", 'latex': 'k_{2\\xi}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 12},
    {'name': 'position_integrator_gain_error_eta', 'unit': '1', 'description': "gain error of the second integrator on ω'_η", 'latex': 'k_{2\\eta}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 12},
    {'name': 'correction_gain_error_x', 'unit': '1', 'description': 'gain error of the correction (torquing) loop, platform axis x', 'latex': 'k_{cx}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 13},
    {'name': 'correction_gain_error_y', 'unit': '1', 'description': 'gain error of the correction (torquing) loop, platform axis y', 'latex': 'k_{cy}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 13},
    {'name': 'correction_gain_error_z', 'unit': '1', 'description': 'gain error of the correction (torquing) loop, azimuth axis z', 'latex': 'k_{cz}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 13},
)
OUTPUTS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'geodetic latitude φ', 'latex': '\\varphi'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'longitude λ', 'latex': '\\lambda'},
    {'name': 'heading', 'unit': 'rad', 'description': 'track angle χ of the ξ axis, from north', 'latex': '\\chi'},
    {'name': 'omega_N', 'unit': 'rad/s', 'description': 'relative angular rate about north', 'latex': '\\omega_N'},
    {'name': 'omega_E', 'unit': 'rad/s', 'description': 'relative angular rate about east', 'latex': '\\omega_E'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north relative velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east relative velocity', 'latex': 'v_E'},
)
INITIAL_CONDITIONS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'initial latitude φ0', 'latex': '\\varphi_0'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'initial longitude λ0', 'latex': '\\lambda_0'},
    {'name': 'heading', 'unit': 'rad', 'description': 'initial track angle χ0', 'latex': '\\chi_0'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'initial north relative velocity', 'latex': 'v_{N0}'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'initial east relative velocity', 'latex': 'v_{E0}'},
)
DOMAIN = ('latitude at ±90° (|u31| = 1): the formulas divide by cos φ', 'semi-major axis a must be positive', 'a + h <= 0: the Earth radius plus height must be positive', 'eccentricity squared must be below 1')
INITIAL_DOMAIN = ('initial latitude at ±90°: the formulas divide by cos φ', 'semi-major axis a must be positive', 'a + h <= 0: the Earth radius plus height must be positive', 'eccentricity squared must be below 1')
MODE_NOTES = {'Schuler': "two channels, each on its own radius, and not a slip: the textbook formula takes one radius, √(R_M R_N), but this model's channel of the velocity error along north runs on the meridian radius R_M (the manual's R_N), ω_N² = g/R_M, and that along east on the prime-vertical radius R_N (the manual's R_E), ω_E² = g/R_N, at any track angle (g the vertical specific force a_ζ at rest). Coupled by the Foucault terms ±2Ω sin φ, their frequencies are the roots ω of (ω² − ω_N²)(ω² − ω_E²) = 4Ω² sin² φ ω², to 3e-5 at every latitude. At the equator the channels part: north about 2π√(R_M/g) = 84.28 min, east about 2π√(R_N/g) = 84.57 min on the Krasovsky ellipsoid (−0.17 % and +0.17 % against the textbook; the rows' periods differ from these by that 3e-5, up to 0.003 min); within a few degrees of it the Foucault split outgrows the difference of the radii and the pair becomes the textbook ω̄ ± Ω|sin φ| (within 0.01 % beyond about 14°); with e2 = 0 it is the textbook pair exactly (at the equator one Schuler row ×2)"}
MODEL_SOURCES_SHA256 = {'models/earth.py': 'ec12172d15c9a23221629c8217666a77c616a9c978ffb43a00af68784a7c9080', 'models/orthodromic.py': 'd07df6ed89dc7a9beda4f248cdc9aa7a658802cbdd9572458e76ae4734d35fc3', 'models/platform.py': '6f1f24a68be4ffd6d6670dc25bc5ca00c17bf15301f383408ccd71ad16455f63'}
