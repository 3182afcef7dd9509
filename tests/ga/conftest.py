"""Makes the synthetic evaluator importable by name, also in spawned worker processes."""

import sys
from pathlib import Path

HELPERS = str(Path(__file__).parent)
if HELPERS not in sys.path:
    sys.path.insert(0, HELPERS)
