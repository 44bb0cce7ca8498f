"""``python -m proofs``: run every proof and the CrossHair contract checks (see :mod:`proofs.runner`)."""

import sys

from proofs.runner import main

sys.exit(main())
