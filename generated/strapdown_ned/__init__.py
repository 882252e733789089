# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/strapdown_ned.py.
# Edit the model definition and run `make derive` again.
"""Generated metadata of the model 'strapdown_ned': Strapdown INS, local-level NED mechanisation on the WGS-84 ellipsoid."""

NAME = 'strapdown_ned'
TITLE = 'Strapdown INS, local-level NED mechanisation on the WGS-84 ellipsoid'
SOURCE = "textbook strapdown mechanisation (Titterton & Weston, 'Strapdown inertial navigation technology', ch. 3; Savage, 'Strapdown analytics')"
STATES = (
    {'name': 'q0', 'unit': '1', 'description': 'attitude quaternion body → NED, scalar part', 'latex': 'q_0'},
    {'name': 'q1', 'unit': '1', 'description': 'attitude quaternion body → NED, first vector part', 'latex': 'q_1'},
    {'name': 'q2', 'unit': '1', 'description': 'attitude quaternion body → NED, second vector part', 'latex': 'q_2'},
    {'name': 'q3', 'unit': '1', 'description': 'attitude quaternion body → NED, third vector part', 'latex': 'q_3'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north ground velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east ground velocity', 'latex': 'v_E'},
    {'name': 'v_D', 'unit': 'm/s', 'description': 'down ground velocity', 'latex': 'v_D'},
    {'name': 'lat', 'unit': 'rad', 'description': 'geodetic latitude φ', 'latex': '\\varphi'},
    {'name': 'lon', 'unit': 'rad', 'description': 'longitude λ', 'latex': '\\lambda'},
    {'name': 'h', 'unit': 'm', 'description': 'height above the ellipsoid', 'latex': 'h'},
)
ERROR_STATES = (
    {'name': 'delta_q0', 'unit': '1', 'description': 'error of the computed attitude quaternion body → NED, scalar part', 'latex': '\\Delta q_0'},
    {'name': 'delta_q1', 'unit': '1', 'description': 'error of the computed attitude quaternion body → NED, first vector part', 'latex': '\\Delta q_1'},
    {'name': 'delta_q2', 'unit': '1', 'description': 'error of the computed attitude quaternion body → NED, second vector part', 'latex': '\\Delta q_2'},
    {'name': 'delta_q3', 'unit': '1', 'description': 'error of the computed attitude quaternion body → NED, third vector part', 'latex': '\\Delta q_3'},
    {'name': 'delta_v_N', 'unit': 'm/s', 'description': 'error of the computed north ground velocity', 'latex': '\\Delta v_N'},
    {'name': 'delta_v_E', 'unit': 'm/s', 'description': 'error of the computed east ground velocity', 'latex': '\\Delta v_E'},
    {'name': 'delta_v_D', 'unit': 'm/s', 'description': 'error of the computed down ground velocity', 'latex': '\\Delta v_D'},
    {'name': 'delta_lat', 'unit': 'rad', 'description': 'error of the computed geodetic latitude φ', 'latex': '\\Delta \\varphi'},
    {'name': 'delta_lon', 'unit': 'rad', 'description': 'error of the computed longitude λ', 'latex': '\\Delta \\lambda'},
    {'name': 'delta_h', 'unit': 'm', 'description': 'error of the computed height above the ellipsoid', 'latex': '\\Delta h'},
)
INPUTS = (
    {'name': 'omega_x', 'unit': 'rad/s', 'description': 'true angular rate ω_ib of the body about its x axis', 'latex': '\\omega_x'},
    {'name': 'omega_y', 'unit': 'rad/s', 'description': 'true angular rate ω_ib of the body about its y axis', 'latex': '\\omega_y'},
    {'name': 'omega_z', 'unit': 'rad/s', 'description': 'true angular rate ω_ib of the body about its z axis', 'latex': '\\omega_z'},
    {'name': 'f_x', 'unit': 'm/s**2', 'description': 'true specific force along the body x axis', 'latex': 'f_x'},
    {'name': 'f_y', 'unit': 'm/s**2', 'description': 'true specific force along the body y axis', 'latex': 'f_y'},
    {'name': 'f_z', 'unit': 'm/s**2', 'description': 'true specific force along the body z axis', 'latex': 'f_z'},
    {'name': 'h_ref', 'unit': 'm', 'description': 'external height reference of the damping loop (true height)', 'latex': 'h_{\\mathrm{ref}}'},
)
PARAMETERS = (
    {'name': 'a', 'unit': 'm', 'description': 'semi-major axis of the ellipsoid', 'latex': 'a', 'default': 6378137.0},
    {'name': 'e2', 'unit': '1', 'description': 'first eccentricity squared', 'latex': 'e^{2}', 'default': 0.0066943799901413165},
    {'name': 'U', 'unit': 'rad/s', 'description': 'Earth rotation rate', 'latex': '\\Omega', 'default': 7.292115e-05},
    {'name': 'gamma_e', 'unit': 'm/s**2', 'description': 'normal gravity on the equator', 'latex': '\\gamma_e', 'default': 9.7803253359},
    {'name': 'gravity_k', 'unit': '1', 'description': 'Somigliana constant k of normal gravity', 'latex': 'k', 'default': 0.00193185265241},
    {'name': 'gravity_m', 'unit': '1', 'description': 'ω²a²b/GM (height dependence of normal gravity)', 'latex': 'm', 'default': 0.00344978650684},
    {'name': 'k_h1', 'unit': '1/s', 'description': 'vertical damping loop: gain on ḣ (0: undamped)', 'latex': 'k_1', 'default': 0.0, 'damping_gain': True, 'example': '0.0293/s', 'example_gives': 'a 300-s loop, damping 0.7'},
    {'name': 'k_h2', 'unit': '1/s**2', 'description': 'vertical damping loop: gain on v̇_D (0: undamped)', 'latex': 'k_2', 'default': 0.0, 'damping_gain': True, 'example': '4.42e-4/s^2', 'example_gives': 'a 300-s loop, damping 0.7'},
)
SOURCES = (
    {'name': 'gyro_bias_x', 'unit': 'rad/s', 'description': 'constant bias of the x gyro', 'latex': 'b_{gx}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_bias_y', 'unit': 'rad/s', 'description': 'constant bias of the y gyro', 'latex': 'b_{gy}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_bias_z', 'unit': 'rad/s', 'description': 'constant bias of the z gyro', 'latex': 'b_{gz}', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_scale_error_x', 'unit': '1', 'description': 'scale-factor error of the x gyro', 'latex': 's_{gx}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'gyro_scale_error_y', 'unit': '1', 'description': 'scale-factor error of the y gyro', 'latex': 's_{gy}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'gyro_scale_error_z', 'unit': '1', 'description': 'scale-factor error of the z gyro', 'latex': 's_{gz}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'gyro_misalignment_xy', 'unit': 'rad', 'description': 'misalignment of the x gyro axis towards body axis y', 'latex': 'm_{gxy}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'gyro_misalignment_xz', 'unit': 'rad', 'description': 'misalignment of the x gyro axis towards body axis z', 'latex': 'm_{gxz}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'gyro_misalignment_yx', 'unit': 'rad', 'description': 'misalignment of the y gyro axis towards body axis x', 'latex': 'm_{gyx}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'gyro_misalignment_yz', 'unit': 'rad', 'description': 'misalignment of the y gyro axis towards body axis z', 'latex': 'm_{gyz}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'gyro_misalignment_zx', 'unit': 'rad', 'description': 'misalignment of the z gyro axis towards body axis x', 'latex': 'm_{gzx}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'gyro_misalignment_zy', 'unit': 'rad', 'description': 'misalignment of the z gyro axis towards body axis y', 'latex': 'm_{gzy}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_bias_x', 'unit': 'm/s**2', 'description': 'constant bias of the x accelerometer', 'latex': 'b_{ax}', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'accel_bias_y', 'unit': 'm/s**2', 'description': 'constant bias of the y accelerometer', 'latex': 'b_{ay}', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'accel_bias_z', 'unit': 'm/s**2', 'description': 'constant bias of the z accelerometer', 'latex': 'b_{az}', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'accel_scale_error_x', 'unit': '1', 'description': 'scale-factor error of the x accelerometer', 'latex': 's_{ax}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'accel_scale_error_y', 'unit': '1', 'description': 'scale-factor error of the y accelerometer', 'latex': 's_{ay}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'accel_scale_error_z', 'unit': '1', 'description': 'scale-factor error of the z accelerometer', 'latex': 's_{az}', 'kind': 'constant', 'display_unit': 'ppm', 'factor': None},
    {'name': 'accel_misalignment_xy', 'unit': 'rad', 'description': 'misalignment of the x accelerometer axis towards body axis y', 'latex': 'm_{axy}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_misalignment_xz', 'unit': 'rad', 'description': 'misalignment of the x accelerometer axis towards body axis z', 'latex': 'm_{axz}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_misalignment_yx', 'unit': 'rad', 'description': 'misalignment of the y accelerometer axis towards body axis x', 'latex': 'm_{ayx}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_misalignment_yz', 'unit': 'rad', 'description': 'misalignment of the y accelerometer axis towards body axis z', 'latex': 'm_{ayz}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_misalignment_zx', 'unit': 'rad', 'description': 'misalignment of the z accelerometer axis towards body axis x', 'latex': 'm_{azx}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'accel_misalignment_zy', 'unit': 'rad', 'description': 'misalignment of the z accelerometer axis towards body axis y', 'latex': 'm_{azy}', 'kind': 'constant', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_roll_error', 'unit': 'rad', 'description': 'error of the initial roll', 'latex': '\\delta\\gamma_0', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_pitch_error', 'unit': 'rad', 'description': 'error of the initial pitch', 'latex': '\\delta\\theta_0', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_heading_error', 'unit': 'rad', 'description': 'error of the initial heading', 'latex': '\\delta\\psi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'initial_velocity_error_N', 'unit': 'm/s', 'description': 'error of the initial north velocity', 'latex': '\\delta v_{N0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_velocity_error_E', 'unit': 'm/s', 'description': 'error of the initial east velocity', 'latex': '\\delta v_{E0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_velocity_error_D', 'unit': 'm/s', 'description': 'error of the initial down velocity', 'latex': '\\delta v_{D0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_position_error_N', 'unit': 'm', 'description': 'error of the initial position towards north, m', 'latex': '\\delta r_{N0}', 'kind': 'initial', 'display_unit': 'm', 'factor': None},
    {'name': 'initial_position_error_E', 'unit': 'm', 'description': 'error of the initial position towards east, m', 'latex': '\\delta r_{E0}', 'kind': 'initial', 'display_unit': 'm', 'factor': None},
    {'name': 'initial_position_error_D', 'unit': 'm', 'description': 'error of the initial position towards down, m', 'latex': '\\delta r_{D0}', 'kind': 'initial', 'display_unit': 'm', 'factor': None},
)
OUTPUTS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'geodetic latitude', 'latex': '\\varphi'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'longitude', 'latex': '\\lambda'},
    {'name': 'height', 'unit': 'm', 'description': 'height above the ellipsoid', 'latex': 'h'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north ground velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east ground velocity', 'latex': 'v_E'},
    {'name': 'v_D', 'unit': 'm/s', 'description': 'down ground velocity', 'latex': 'v_D'},
    {'name': 'roll', 'unit': 'rad', 'description': 'roll angle (Z-Y-X Euler angles body → NED)', 'latex': '\\gamma'},
    {'name': 'pitch', 'unit': 'rad', 'description': 'pitch angle', 'latex': '\\theta'},
    {'name': 'heading', 'unit': 'rad', 'description': 'heading (true, from north towards east)', 'latex': '\\psi'},
)
INITIAL_CONDITIONS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'initial geodetic latitude', 'latex': '\\varphi_0'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'initial longitude', 'latex': '\\lambda_0'},
    {'name': 'height', 'unit': 'm', 'description': 'initial height', 'latex': 'h_0'},
    {'name': 'v_N0', 'unit': 'm/s', 'description': 'initial north ground velocity', 'latex': 'v_{N0}'},
    {'name': 'v_E0', 'unit': 'm/s', 'description': 'initial east ground velocity', 'latex': 'v_{E0}'},
    {'name': 'v_D0', 'unit': 'm/s', 'description': 'initial down ground velocity', 'latex': 'v_{D0}'},
    {'name': 'roll', 'unit': 'rad', 'description': 'initial roll', 'latex': '\\gamma_0'},
    {'name': 'pitch', 'unit': 'rad', 'description': 'initial pitch', 'latex': '\\theta_0'},
    {'name': 'heading', 'unit': 'rad', 'description': 'initial heading', 'latex': '\\psi_0'},
)
DOMAIN = ('latitude at ±90°: λ̇ divides by cos φ', 'pitch at ±90°: roll and heading are undefined', 'attitude quaternion of zero length', 'a <= 0: the semi-major axis must be positive', 'eccentricity squared must be below 1', 'normal gravity on the equator gamma_e must be positive')
INITIAL_DOMAIN = ('initial latitude at ±90°: longitude is undefined', 'initial pitch at ±90°: roll and heading are undefined', 'a <= 0: the semi-major axis must be positive', 'eccentricity squared must be below 1', 'normal gravity on the equator gamma_e must be positive')
MODE_NOTES = {'Schuler': "not the textbook pair, and not a slip: the textbook formula leaves out the vertical channel and the ellipsoid. The Coriolis terms ±2Ω cos φ (δv_E ↔ δv_D) couple the unstable vertical channel (λ² = ∂γ/∂h) to the east channel and stiffen it by (2Ω cos φ)² ω_s²/(ω_s² + ∂γ/∂h) ≈ (2Ω cos φ)²/3, and each channel has its own radius: north ω_N² = g/R_M (meridian radius), east ω_E² = g/R_N + (2Ω cos φ)² ω_s²/(ω_s² + ∂γ/∂h) (prime vertical; ω_s² = g/√(R_M R_N)). Coupled by the Foucault terms ±2Ω sin φ, their frequencies are the roots ω of (ω² − ω_N²)(ω² − ω_E²) = 4Ω² sin² φ ω², which give this model's two Schuler periods (vertical channel undamped) to 6e-6 at every latitude (−0.050 % and −0.045 % against the textbook at 50°). Where the Foucault split outgrows the difference of the radii (|φ| ≥ 15°) that is ω̄ ± Ω|sin φ| with ω̄² = g/R + Ω² sin² φ + (2Ω cos φ)²/6, again to 6e-6 (2.6e-5 at 5°); at the equator the channels part, north 2π/ω_N and east 2π/ω_E", 'vertical channel': "not √(R/2g), and not a slip: normal gravity falls with height at ∂γ/∂h = (2γ/a)(1 + f + m − 2f sin² φ), not 2g/R (+0.35 % at 50°), and the Coriolis coupling with the east channel takes (2Ω cos φ)² ∂γ/∂h/(∂γ/∂h + g/R) ≈ (2/3)(2Ω cos φ)² off λ²; together they give this model's λ to 1e-6 (−0.077 % in the time constant at 50°); with the damping gains k₁, k₂ set the channel is the loop's, not this"}
MODEL_SOURCES_SHA256 = {'models/earth.py': 'ec12172d15c9a23221629c8217666a77c616a9c978ffb43a00af68784a7c9080', 'models/platform.py': '6f1f24a68be4ffd6d6670dc25bc5ca00c17bf15301f383408ccd71ad16455f63', 'models/strapdown_ned.py': '917730fd4bf2c5cd8191b92c00bc7ea3af0d75a1494ed07f73ceef3685362bbe'}
