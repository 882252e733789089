"""Data files shipped with the package (the built-in 802m accuracy spec)."""
