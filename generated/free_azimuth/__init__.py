# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/free_azimuth.py.
# Edit the model definition and run `make derive` again.
"""Generated metadata of the model 'free_azimuth': Free-azimuth platform INS (IS-1-72A), rebuilt."""

NAME = 'free_azimuth'
TITLE = 'Free-azimuth platform INS (IS-1-72A), rebuilt'
SOURCE = '002: information-processing algorithm of a free-azimuth INS (IS-1-72A)'
STATES = (
    {'name': 'Phi', 'unit': 'rad', 'description': 'orthodromic latitude Φ', 'latex': '\\Phi'},
    {'name': 'Lam', 'unit': 'rad', 'description': 'orthodromic longitude Λ', 'latex': '\\Lambda'},
    {'name': 'A', 'unit': 'rad', 'description': "angle A from the orthodromic trihedron ξη to the reference ξ'η'", 'latex': 'A'},
    {'name': 'V_x', 'unit': 'm/s', 'description': "absolute horizontal velocity along the reference axis ξ'", 'latex': 'V_x'},
    {'name': 'V_y', 'unit': 'm/s', 'description': "absolute horizontal velocity along the reference axis η'", 'latex': 'V_y'},
)
ERROR_STATES = (
    {'name': 'delta_Phi', 'unit': 'rad', 'description': 'error of the computed orthodromic latitude Φ', 'latex': '\\Delta \\Phi'},
    {'name': 'delta_Lam', 'unit': 'rad', 'description': 'error of the computed orthodromic longitude Λ', 'latex': '\\Delta \\Lambda'},
    {'name': 'delta_A', 'unit': 'rad', 'description': "error of the computed angle A from the orthodromic trihedron ξη to the reference ξ'η'", 'latex': '\\Delta A'},
    {'name': 'delta_V_x', 'unit': 'm/s', 'description': "error of the computed absolute horizontal velocity along the reference axis ξ'", 'latex': '\\Delta V_x'},
    {'name': 'delta_V_y', 'unit': 'm/s', 'description': "error of the computed absolute horizontal velocity along the reference axis η'", 'latex': '\\Delta V_y'},
    {'name': 'alpha_x', 'unit': 'rad', 'description': "platform deviation about x (≈ξ') from the reference", 'latex': '\\alpha'},
    {'name': 'alpha_y', 'unit': 'rad', 'description': "platform deviation about y (≈η') from the reference", 'latex': '\\beta'},
    {'name': 'alpha_z', 'unit': 'rad', 'description': 'platform deviation in azimuth from the reference', 'latex': '\\delta'},
)
INPUTS = (
    {'name': 'a_x', 'unit': 'm/s**2', 'description': "true apparent acceleration along the reference axis ξ'", 'latex': 'a_x'},
    {'name': 'a_y', 'unit': 'm/s**2', 'description': "true apparent acceleration along the reference axis η'", 'latex': 'a_y'},
    {'name': 'a_zeta', 'unit': 'm/s**2', 'description': 'true apparent acceleration along the vertical (≈ +g at rest)', 'latex': 'a_\\zeta'},
    {'name': 'V_zeta', 'unit': 'm/s', 'description': 'vertical velocity V_h (given from outside)', 'latex': 'V_h'},
)
PARAMETERS = (
    {'name': 'R', 'unit': 'm', 'description': 'platform tuning radius = radius of the navigation sphere', 'latex': 'R', 'default': 6411000.0},
    {'name': 'U', 'unit': 'rad/s', 'description': 'Earth rotation rate', 'latex': 'U', 'default': 7.292115e-05},
    {'name': 'orth_latitude', 'unit': 'rad', 'description': 'geographic latitude φ_o of the orthodromic origin', 'latex': '\\varphi_o', 'default': 0.0},
    {'name': 'orth_longitude', 'unit': 'rad', 'description': 'longitude λ_o of the orthodromic origin', 'latex': '\\lambda_o', 'default': 0.0},
    {'name': 'orth_azimuth', 'unit': 'rad', 'description': 'azimuth N_o of the orthodrome at its origin (from north)', 'latex': 'N_o', 'default': 1.5707963267948966},
)
SOURCES = (
    {'name': 'initial_tilt_x', 'unit': 'rad', 'description': 'initial platform deviation about x (gravity levelling: 2α_g)', 'latex': '\\alpha_0', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': 1},
    {'name': 'initial_tilt_y', 'unit': 'rad', 'description': 'initial platform deviation about y (gravity levelling: 2β_g)', 'latex': '\\beta_0', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': 1},
    {'name': 'initial_azimuth_error', 'unit': 'rad', 'description': 'initial platform azimuth deviation from the reference trihedron', 'latex': '\\delta_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 2},
    {'name': 'initial_A_error', 'unit': 'rad', 'description': 'error of the initial angle A set into the computer', 'latex': '\\Delta A_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 2},
    {'name': 'initial_velocity_error_x', 'unit': 'm/s', 'description': 'error of the initial velocity integrator x', 'latex': '\\Delta V_{x0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': 3},
    {'name': 'initial_velocity_error_y', 'unit': 'm/s', 'description': 'error of the initial velocity integrator y', 'latex': '\\Delta V_{y0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': 3},
    {'name': 'initial_Phi_error', 'unit': 'rad', 'description': 'error of the initial orthodromic latitude', 'latex': '\\Delta\\Phi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 4},
    {'name': 'initial_Lam_error', 'unit': 'rad', 'description': 'error of the initial orthodromic longitude', 'latex': '\\Delta\\Lambda_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': 4},
    {'name': 'gyro_drift_x', 'unit': 'rad/s', 'description': 'residual (uncompensated part of the) drift of the gyro about x', 'latex': '\\omega_{dx}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 5},
    {'name': 'gyro_drift_y', 'unit': 'rad/s', 'description': 'residual (uncompensated part of the) drift of the gyro about y', 'latex': '\\omega_{dy}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 5},
    {'name': 'gyro_drift_z', 'unit': 'rad/s', 'description': 'azimuth drift (not compensated in this system)', 'latex': '\\omega_{dz}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 6},
    {'name': 'accel_bias_x', 'unit': 'm/s**2', 'description': 'zero offset of the x accelerometer', 'latex': '\\Delta a_x', 'kind': 'constant', 'display_unit': 'ug', 'factor': 7},
    {'name': 'accel_bias_y', 'unit': 'm/s**2', 'description': 'zero offset of the y accelerometer', 'latex': '\\Delta a_y', 'kind': 'constant', 'display_unit': 'ug', 'factor': 7},
    {'name': 'velocity_integrator_offset_x', 'unit': 'm/s**2', 'description': 'zero offset of the first (velocity) integrator x, at its input', 'latex': '\\delta_{1x}', 'kind': 'constant', 'display_unit': 'ug', 'factor': 8},
    {'name': 'velocity_integrator_offset_y', 'unit': 'm/s**2', 'description': 'zero offset of the first (velocity) integrator y, at its input', 'latex': '\\delta_{1y}', 'kind': 'constant', 'display_unit': 'ug', 'factor': 8},
    {'name': 'position_integrator_offset_Phi', 'unit': 'rad/s', 'description': 'zero offset of the second integrator of (8.35): rate added to Φ̇', 'latex': '\\delta_{2\\Phi}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 9},
    {'name': 'position_integrator_offset_Lam', 'unit': 'rad/s', 'description': 'zero offset of the second integrator of (8.35): rate added to Λ̇', 'latex': '\\delta_{2\\Lambda}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': 9},
    {'name': 'accel_scale_error_x', 'unit': '1', 'description': 'scale-factor error of the x accelerometer', 'latex': 'k_{ax}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 10},
    {'name': 'accel_scale_error_y', 'unit': '1', 'description': 'scale-factor error of the y accelerometer', 'latex': 'k_{ay}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 10},
    {'name': 'velocity_integrator_gain_error_x', 'unit': '1', 'description': 'gain error of the first (velocity) integrator x', 'latex': 'k_{1x}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 11},
    {'name': 'velocity_integrator_gain_error_y', 'unit': '1', 'description': 'gain error of the first (velocity) integrator y', 'latex': 'k_{1y}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 11},
    {'name': 'position_integrator_gain_error_Phi', 'unit': '1', 'description': 'gain error of the second integrator of Φ', 'latex': 'k_{2\\Phi}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 12},
    {'name': 'position_integrator_gain_error_Lam', 'unit': '1', 'description': 'gain error of the second integrator of Λ', 'latex': 'k_{2\\Lambda}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 12},
    {'name': 'correction_gain_error_x', 'unit': '1', 'description': 'gain error of the correction loop about x (tuning 1/R)', 'latex': 'k_{cx}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 13},
    {'name': 'correction_gain_error_y', 'unit': '1', 'description': 'gain error of the correction loop about y (tuning 1/R)', 'latex': 'k_{cy}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': 13},
)
OUTPUTS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'geographic (geocentric) latitude φ', 'latex': '\\varphi'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'longitude λ', 'latex': '\\lambda'},
    {'name': 'heading', 'unit': 'rad', 'description': "true azimuth ψ of the reference axis ξ'", 'latex': '\\psi'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north relative velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east relative velocity', 'latex': 'v_E'},
)
INITIAL_CONDITIONS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'initial latitude φ0', 'latex': '\\varphi_0'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'initial longitude λ0', 'latex': '\\lambda_0'},
    {'name': 'heading', 'unit': 'rad', 'description': "initial true azimuth ψ0 of the reference axis ξ'", 'latex': '\\psi_0'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'initial north relative velocity', 'latex': 'v_{N0}'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'initial east relative velocity', 'latex': 'v_{E0}'},
)
DOMAIN = ('orthodromic latitude at ±90°: (8.35) divides by cos Φ', 'latitude at ±90°: north and east are undefined at the geographic pole', 'R <= 0: the tuning radius must be positive')
INITIAL_DOMAIN = ('initial latitude at ±90°: heading is undefined', 'R <= 0: the tuning radius must be positive')
MODE_NOTES = {'Schuler': "two channels, not a Foucault pair, and not a slip: the reference axes ξ'η' do not turn about the vertical (no azimuth command: the wander angle A takes up the Earth's vertical rate, Ȧ = −U k_ζ) and the integrators hold the absolute velocity (no Coriolis terms), so nothing splits the Schuler pair by Ω sin φ; but at rest the platform is torqued at the horizontal Earth rate Ω cos φ about north, and α̇ = α × ω couples the tilt about the horizontal axis across it (the channel of the velocity error along north) with the azimuth error α_z (the gyrocompass coupling), which stiffens that channel: ω² = g/R + Ω² cos² φ (g the vertical specific force a_ζ at rest, R the model's tuning radius; 84.65 min against 2π√(R/g) = 84.76 min at −30°, −0.17 % at the equator), exactly, at any heading; the other channel is the textbook 2π√(R/g). These are the wander-frame states' modes: the outputs (latitude, longitude, heading) are read through A, which turns at rest, and show the Schuler oscillation split by ±U sin φ (Schuler ∓ Foucault, 88.7 and 81.0 min at 50°)"}
MODEL_SOURCES_SHA256 = {'models/earth.py': 'ec12172d15c9a23221629c8217666a77c616a9c978ffb43a00af68784a7c9080', 'models/free_azimuth.py': 'ce7d466bede94d3af87e0cdfd67a10d8ba2f20f6501d5b29987485e525c0e221', 'models/platform.py': '6f1f24a68be4ffd6d6670dc25bc5ca00c17bf15301f383408ccd71ad16455f63'}
