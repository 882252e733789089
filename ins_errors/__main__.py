"""``python -m ins_errors``: the ``ins-errors`` command."""

import sys

from ins_errors.cli import main

if __name__ == "__main__":
    sys.exit(main())
