"""railcheck.studies: what the FE and the kinematics are worth. :mod:`.bench` (the
cantilever against Timoshenko), :mod:`.convergence` (accuracy against time),
:mod:`.mechanism` (seed 002's planar mechanisms: mobility, tracer paths, pages)."""
