"""``python -m rocknroller``: the same as the ``rocknroller`` console script."""

import sys

from rocknroller.cli import main

sys.exit(main())
