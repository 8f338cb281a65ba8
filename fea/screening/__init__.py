"""railcheck.fea.screening: exact screens of load histories over a part's nodes.

Which nodes can hold the cycle's von Mises peak or its lowest fatigue factor, so that only
those are evaluated at every step; the results equal evaluating every node at every step
to rounding. Modules, upstream first:

* :mod:`.subspace` a history's principal subspace and the steps read along its path;
* :mod:`.box` box bounds at every node from the coefficients' ranges
  (:class:`CoefficientBox`, :class:`SampledBounds`);
* :mod:`.span` the coefficients a group of histories spans (:func:`history_span`);
* :mod:`.bounds` sampled bounds at the nodes a box keeps, fatigue bounds, first nodes;
* :mod:`.tuning` the tunables (sizes and shares measured on the rig);
* :mod:`.screens` a part's fields at its verdict nodes per column set (:class:`Screen`);
* :mod:`.exact` exact values at the kept nodes;
* :mod:`.passes` the bound tests, thresholds and a group's first pass;
* :mod:`.alone` a history screened alone; :mod:`.batch` a group's histories together;
* :mod:`.groups` the entry points: :func:`peak_and_fatigue`, :func:`von_mises_peak`,
  :func:`fatigue_min` over many settings' histories at once.

The sweep (:mod:`railcheck.sweep.chunk`), the check's cycle (:mod:`railcheck.model.cycle`)
and the superposition (:mod:`railcheck.fea.superpose`) use it through this namespace. Each
name is imported from its module on first use (PEP 562), so importing one module does not
import the rest. SI throughout (Pa, m).
"""

from importlib import import_module

#: public name -> the module that defines it
_WHERE = {
    "screened_alone": "alone",
    "Batch": "batch",
    "ExactSource": "batch",
    "box_and_factor": "batch",
    "by_component": "batch",
    "BASIS_TRIAL_NODES": "bounds",
    "MEAN_ROUNDING": "bounds",
    "Projected": "bounds",
    "basis_trial_nodes": "bounds",
    "box_basis": "bounds",
    "box_basis_and_coordinates": "bounds",
    "fatigue_bounds": "bounds",
    "fatigue_bounds_by_midranges": "bounds",
    "fatigue_sampled": "bounds",
    "first_nodes": "bounds",
    "history_bounds": "bounds",
    "history_box_bounds": "bounds",
    "interval_von_mises": "bounds",
    "midrange_box": "bounds",
    "peak_candidates": "bounds",
    "project_history": "bounds",
    "sampled_at": "bounds",
    "sampled_bounds": "bounds",
    "sampled_pairs": "bounds",
    "BOX_TAKEN_STEPS": "box",
    "BOX_WIDENING": "box",
    "CoefficientBox": "box",
    "FLOAT32_EPS": "box",
    "SampledBounds": "box",
    "box_bounds": "box",
    "component_norms": "box",
    "project": "box",
    "von_mises_interval_bound": "box",
    "von_mises_norm_bound": "box",
    "ellipse_fatigue_bounds": "exact",
    "enclosing_ellipse": "exact",
    "exact_at": "exact",
    "exact_von_mises2": "exact",
    "fatigue_exact": "exact",
    "fatigue_exact_planar": "exact",
    "tip_peak": "exact",
    "fatigue_min": "groups",
    "group_box": "groups",
    "in_span": "groups",
    "peak_and_fatigue": "groups",
    "screened_group": "groups",
    "von_mises_peak": "groups",
    "PairsRead": "passes",
    "box_union": "passes",
    "can_beat": "passes",
    "fatigue_may_pass": "passes",
    "first_per_row": "passes",
    "group_nodes": "passes",
    "group_thresholds": "passes",
    "over_sets": "passes",
    "peak_may_pass": "passes",
    "restricted_screen": "passes",
    "set_cuts": "passes",
    "Screen": "screens",
    "ScreenBounds": "screens",
    "fatigue_factors": "screens",
    "hull_steps": "screens",
    "make_screen": "screens",
    "make_screens": "screens",
    "node_slab": "screens",
    "screen_bounds": "screens",
    "screen_of": "screens",
    "value_slices": "screens",
    "verdict_nodes": "screens",
    "SPAN_RANK": "span",
    "SPAN_RESIDUAL": "span",
    "SPAN_STRIDE": "span",
    "Span": "span",
    "history_span": "span",
    "CHORD_SHARE": "subspace",
    "CHUNK_VALUES": "subspace",
    "FIRST_NODES": "subspace",
    "FIRST_SAMPLES": "subspace",
    "MAX_RANK": "subspace",
    "MAX_SAMPLES": "subspace",
    "MIN_STEPS": "subspace",
    "REDUCED_RANK": "subspace",
    "RESIDUAL_SHARE": "subspace",
    "SLACK": "subspace",
    "Subspace": "subspace",
    "Subspaces": "subspace",
    "TOUCHED_STEPS": "subspace",
    "VM_FACTOR": "subspace",
    "applies": "subspace",
    "chord_gaps": "subspace",
    "chord_gaps_of": "subspace",
    "column_scale": "subspace",
    "history_blocks": "subspace",
    "midrange_bound": "subspace",
    "nearest_to_box_centre": "subspace",
    "padded_indices": "subspace",
    "path_sample_mask": "subspace",
    "path_samples": "subspace",
    "principal_subspace": "subspace",
    "principal_subspaces": "subspace",
    "refined_masks": "subspace",
    "refined_samples": "subspace",
    "scaled": "subspace",
    "steps_of": "subspace",
    "subspace_ranks": "subspace",
    "touched_of": "subspace",
    "touched_steps": "subspace",
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(import_module(f"{__name__}.{_WHERE[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
