"""railcheck.report: what a person reads. :mod:`.text` (console tables), :mod:`.html`
(report.html), :mod:`.render` (pyvista pictures of the parts), :mod:`.plots` (matplotlib
plots). Units at this edge: mm, MPa, N, N·m, deg. pyvista and matplotlib are imported
inside the functions that draw."""
