"""Make the shared synthetic-cloud helpers of this folder importable (no __init__.py here)."""

import sys
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
