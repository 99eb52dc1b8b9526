"""sylva: grow plants, their textures and the worlds they stand in."""

from .errors import GrowthLimitError, LSystemSyntaxError, SylvaError

__all__ = ["GrowthLimitError", "LSystemSyntaxError", "SylvaError"]
__version__ = "0.1.0"
