"""Scene texts shared by the tests (TOML)."""

#: seed 000's final design ("CUMPLE Y MONTABLE", 3.3.6), mechanism only
FINAL_DESIGN = """
[mechanism]
kind = "four-bar"
crank = "480 mm"
coupler = "840 mm"
rocker = "780 mm"
ground = "1020 mm"
"""

#: PF_4b_003_v2 alone with the seed's explicit loads (4.2.1): no linkage runs
PLATE_LOADS = """
[check]
parts = ["PF_4b_003_v2"]
[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
"""
