# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/north_pointing.py.
# Edit the model definition and run `make derive` again.
"""Generated metadata of the model 'north_pointing': North-pointing local-level gyro-platform INS."""

NAME = 'north_pointing'
TITLE = 'North-pointing local-level gyro-platform INS'
SOURCE = "001: lab report 'Error-propagation characteristics of an INS' (north-pointing platform, static base)"
STATES = (
    {'name': 'V_E', 'unit': 'm/s', 'description': 'east ground velocity', 'latex': 'V_E'},
    {'name': 'V_N', 'unit': 'm/s', 'description': 'north ground velocity', 'latex': 'V_N'},
    {'name': 'phi', 'unit': 'rad', 'description': 'latitude φ', 'latex': '\\varphi'},
    {'name': 'lam', 'unit': 'rad', 'description': 'longitude λ', 'latex': '\\lambda'},
)
ERROR_STATES = (
    {'name': 'delta_v_E', 'unit': 'm/s', 'description': 'east velocity error', 'latex': '\\delta v_E'},
    {'name': 'delta_v_N', 'unit': 'm/s', 'description': 'north velocity error', 'latex': '\\delta v_N'},
    {'name': 'delta_latitude', 'unit': 'rad', 'description': 'latitude error', 'latex': '\\delta\\varphi'},
    {'name': 'delta_longitude', 'unit': 'rad', 'description': 'longitude error', 'latex': '\\delta\\lambda'},
    {'name': 'alpha_E', 'unit': 'rad', 'description': 'platform error angle about east (level)', 'latex': '\\alpha_E'},
    {'name': 'alpha_N', 'unit': 'rad', 'description': 'platform error angle about north (level)', 'latex': '\\alpha_N'},
    {'name': 'alpha_U', 'unit': 'rad', 'description': 'platform error angle about up (azimuth)', 'latex': '\\alpha_U'},
)
INPUTS = (
    {'name': 'a_E', 'unit': 'm/s**2', 'description': 'true specific force along east (0 at rest)', 'latex': 'a_E'},
    {'name': 'a_N', 'unit': 'm/s**2', 'description': 'true specific force along north (0 at rest)', 'latex': 'a_N'},
    {'name': 'h', 'unit': 'm', 'description': 'height above the Earth model (given from outside)', 'latex': 'h'},
)
PARAMETERS = (
    {'name': 'R', 'unit': 'm', 'description': 'Earth radius (sphere) or semi-major axis (ellipsoid)', 'latex': 'R', 'default': 6371000.0},
    {'name': 'ecc2', 'unit': '1', 'description': 'first eccentricity squared (0: sphere)', 'latex': 'e^{2}', 'default': 0.0},
    {'name': 'U', 'unit': 'rad/s', 'description': 'Earth rotation rate', 'latex': '\\Omega', 'default': 7.292115e-05},
    {'name': 'g', 'unit': 'm/s**2', 'description': 'gravity (plumb line), normal to the local level', 'latex': 'g', 'default': 9.80665},
)
SOURCES = (
    {'name': 'gyro_drift_east', 'unit': 'rad/s', 'description': 'constant drift rate of the east gyro (report: Ex)', 'latex': '\\varepsilon_E', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_drift_north', 'unit': 'rad/s', 'description': 'constant drift rate of the north gyro (report: Ey)', 'latex': '\\varepsilon_N', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'gyro_drift_up', 'unit': 'rad/s', 'description': 'constant drift rate of the azimuth gyro (report: Ez)', 'latex': '\\varepsilon_U', 'kind': 'constant', 'display_unit': 'deg/h', 'factor': None},
    {'name': 'accel_bias_east', 'unit': 'm/s**2', 'description': 'constant bias of the east accelerometer (report: Dx)', 'latex': '\\nabla_E', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'accel_bias_north', 'unit': 'm/s**2', 'description': 'constant bias of the north accelerometer (report: Dy)', 'latex': '\\nabla_N', 'kind': 'constant', 'display_unit': 'ug', 'factor': None},
    {'name': 'initial_velocity_error_east', 'unit': 'm/s', 'description': 'error of the initial east velocity set into the computer (report: Dx0)', 'latex': '\\delta v_{E0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_velocity_error_north', 'unit': 'm/s', 'description': 'error of the initial north velocity set into the computer (report: Dy0)', 'latex': '\\delta v_{N0}', 'kind': 'initial', 'display_unit': 'm/s', 'factor': None},
    {'name': 'initial_latitude_error', 'unit': 'rad', 'description': 'error of the initial latitude set into the computer (report: L0)', 'latex': '\\delta\\varphi_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'initial_longitude_error', 'unit': 'rad', 'description': 'error of the initial longitude set into the computer (report: N0)', 'latex': '\\delta\\lambda_0', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
    {'name': 'initial_tilt_east', 'unit': 'rad', 'description': 'initial platform levelling error about east (report: Qx0)', 'latex': '\\alpha_{E0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_tilt_north', 'unit': 'rad', 'description': 'initial platform levelling error about north (report: Qy0)', 'latex': '\\alpha_{N0}', 'kind': 'initial', 'display_unit': 'arcsec', 'factor': None},
    {'name': 'initial_azimuth_error', 'unit': 'rad', 'description': 'initial platform azimuth alignment error (report: Qz0)', 'latex': '\\alpha_{U0}', 'kind': 'initial', 'display_unit': 'arcmin', 'factor': None},
)
OUTPUTS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'latitude φ', 'latex': '\\varphi'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'longitude λ', 'latex': '\\lambda'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'north ground velocity', 'latex': 'v_N'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'east ground velocity', 'latex': 'v_E'},
)
INITIAL_CONDITIONS = (
    {'name': 'latitude', 'unit': 'rad', 'description': 'initial latitude φ0', 'latex': '\\varphi_0'},
    {'name': 'longitude', 'unit': 'rad', 'description': 'initial longitude λ0', 'latex': '\\lambda_0'},
    {'name': 'v_N', 'unit': 'm/s', 'description': 'initial north ground velocity', 'latex': 'v_{N0}'},
    {'name': 'v_E', 'unit': 'm/s', 'description': 'initial east ground velocity', 'latex': 'v_{E0}'},
)
DOMAIN = ('latitude at or beyond ±90°: the formulas divide by cos φ (tan φ, sec φ)', 'Earth radius R must be positive', 'gravity g must be positive', 'eccentricity squared ecc2 must be below 1', 'eccentricity squared ecc2 must not be negative', "R + h must be positive: height below the Earth's centre")
INITIAL_DOMAIN = ('initial latitude at or beyond ±90°: the formulas divide by cos φ (tan φ, sec φ)', 'Earth radius R must be positive', 'gravity g must be positive', 'eccentricity squared ecc2 must be below 1', 'eccentricity squared ecc2 must not be negative', "R + h must be positive: height below the Earth's centre")
MODEL_SOURCES_SHA256 = {'models/earth.py': 'ec12172d15c9a23221629c8217666a77c616a9c978ffb43a00af68784a7c9080', 'models/north_pointing.py': 'eb811bd54b6d0c470d4acde69e7f8a27a4f5651b330383d357fcaaf065abaca6', 'models/platform.py': '6f1f24a68be4ffd6d6670dc25bc5ca00c17bf15301f383408ccd71ad16455f63'}
