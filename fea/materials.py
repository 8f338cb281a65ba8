"""A small material library. SI: Pa, kg/m^3.

The fatigue limit defaults to sigma_u / 2 (seed 000, 3.3.1: "resistente a fatiga si las
tensiones son menores que la mitad de su tensión de rotura").
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Material:
    name: str
    youngs_modulus: float  # Pa
    poisson_ratio: float
    ultimate_strength: float  # Pa
    density: float  # kg/m^3
    source: str
    yield_strength: float = 0.0  # Pa (for the ASME-elliptic fatigue criterion)

    @property
    def fatigue_limit(self) -> float:
        """sigma_u / 2 (Pa), the seed's fatigue rule."""
        return self.ultimate_strength / 2.0

    @property
    def lame(self) -> tuple[float, float]:
        """(lambda, mu) in Pa."""
        E, nu = self.youngs_modulus, self.poisson_ratio
        return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


MATERIALS: dict[str, Material] = {
    "steel": Material(
        "steel",
        210e9,
        0.30,
        750e6,
        7850.0,
        "quenched and tempered C45/C50 class; seed 000: sigma_u/2 = 375 MPa; yield 490 MPa (EN 10083-2 C45+QT, d <= 16 mm)",
        490e6,
    ),
    "S235": Material("S235", 210e9, 0.30, 360e6, 7850.0, "EN 10025-2, fu = 360 MPa (t < 100 mm)", 235e6),
    "S355": Material("S355", 210e9, 0.30, 470e6, 7850.0, "EN 10025-2, fu = 470 MPa (t < 100 mm)", 355e6),
    "ABS": Material("ABS", 2.3e9, 0.37, 40e6, 1050.0, "typical moulded ABS", 40e6),
}

#: the seed's fatigue limit; a steel whose sigma_u/2 is below it earns a warning
SEED_FATIGUE_LIMIT = 375e6


def limit_warning(material: Material, explicit_limit: float | None) -> str | None:
    """A warning when the sigma_u/2 rule is applied to a steel weaker than the seed's."""
    if explicit_limit is None and material.name != "ABS" and material.fatigue_limit < SEED_FATIGUE_LIMIT:
        return (
            f"material {material.name}: the sigma_u/2 rule gives {material.fatigue_limit / 1e6:.0f} MPa, "
            f"below the seed's {SEED_FATIGUE_LIMIT / 1e6:.0f} MPa for quenched and tempered steel"
        )
    return None
