"""``python -m rocknroller.cli``: the same as the ``rocknroller`` console script."""

import sys

from rocknroller.cli import main

if __name__ == "__main__":
    sys.exit(main())
