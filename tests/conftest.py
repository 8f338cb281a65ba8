import math

import pytest


def agree_sig(a: float, b: float, figures: int = 4) -> bool:
    """True when ``a`` agrees with the published ``b`` to ``figures`` significant figures
    (within half a unit of the last published figure)."""
    if b == 0:
        return abs(a) < 10 ** (-figures)
    unit = 10 ** (math.floor(math.log10(abs(b))) - (figures - 1))
    return abs(a - b) <= 0.5 * unit


@pytest.fixture
def sig():
    return agree_sig
