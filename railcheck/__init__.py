"""railcheck: design check for reconfigurable planar linkages built from linear-guide rails."""

__version__ = "0.1.0"
