"""``python -m rotor_host.cli``: the ``rotor-host`` command."""

import sys

from . import main

sys.exit(main())
