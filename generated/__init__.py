"""Generated code of every model (written by `make derive`)."""

MODELS = ('orthodromic', 'north_pointing', 'free_azimuth', 'geodetic_vertical', 'strapdown_ned')
