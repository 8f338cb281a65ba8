"""railcheck: design check for reconfigurable planar linkages built from linear-guide rails."""

__version__ = "0.1.0"

# The domain packages live at the top of the source tree (fea/, geometry/, loads/,
# kinematics/) but are installed inside this package (railcheck.fea, ...) so that no
# global package named "fea" or "geometry" is installed. In a source checkout, not
# installed, they are found next to this directory:
import os as _os

_root = _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__)))
if not _os.path.isdir(_os.path.join(_os.path.dirname(__file__), "fea")) and \
        _os.path.isdir(_os.path.join(_root, "fea")):
    __path__.append(_root)
del _os, _root
