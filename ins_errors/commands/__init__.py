"""Subcommands of the ``ins-errors`` command line, one module each."""
