"""``python -m locustjump.cli``."""

import sys

from locustjump.cli import main

sys.exit(main())
