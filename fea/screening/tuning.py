"""The screens' tunables: chunk sizes, node counts and shares, each measured on the rig's
histories (the comment above each says how). Read as ``tuning.NAME`` so that a test can
set one for every module of the package."""

from __future__ import annotations

from . import subspace

#: floats per temporary of a group's products (nodes x settings x steps)
CHUNK_VALUES = 8_000_000
#: floats per temporary of the exact evaluations at every step (6 x nodes x histories x
#: steps: :func:`exact_at`, :meth:`Batch.exact`, :func:`exact_von_mises2`), 2 MB: each
#: product's result is read again for von Mises and the extremes while in cache
#: (measured: docs/changelog.md, "The measurements behind tuned constants")
EXACT_VALUES = 1 << 18
TOP_NODES = 64  # nodes evaluated first for the lower bound
SLACK = subspace.SLACK  # relative margin on the bounds (rounding)
#: nodes of best box bound (per criterion) read at the sampled steps, whose best sampled
#: values are then evaluated exactly for the thresholds (many coefficients)
BOX_FIRST = 128
#: of those, the nodes of best sampled value (each criterion) evaluated exactly for a batch's
#: thresholds (40 captured calls, 2,702 histories, one thread, medians of five alternating
#: rounds: 8 nodes 0.943 of the time of 16, 4 nodes 0.998 of 8; results bit for bit the same)
THRESHOLD_NODES = 8
#: a history whose group box keeps more than this share of the nodes is bounded in its own
#: principal subspace at every node instead (and its thresholds taken again from that box)
LOOSE_SHARE = 0.25
#: nodes of best bound (each criterion) of a group's common shape whose exact values give
#: every history of the group its first thresholds (:func:`group_thresholds`)
GROUP_CANDIDATES = 8
#: a group's histories are screened on the nodes that can matter to one of them when
#: those are fewer than this share of the part's (:func:`group_nodes`)
GROUP_SHARE = 0.7
#: histories screened as one group at most (:func:`screened_group`; a larger group is
#: cut into consecutive ones): the group's box, basis and node restriction are shared by
#: more histories, but their common box is looser (captured crank-rail and PF_4b_006
#: histories, one thread: 6.0 ms per history in groups of 64, 6.5 in groups of 128, 7.4-8.3
#: in one group per hole pair of 600)
GROUP_MOST = 64
#: verdict nodes per slab of a part's fields read by :func:`make_screens` (a rail's: 6 x 128
#: nodes x 89 columns, 0.5 MB, in cache while every hole pair's columns are taken from it)
GATHER_NODES = 128
#: histories x nodes whose box bounds a batch of :func:`screened_group` holds at once
#: (about 60 bytes each, in float32)
BATCH_PAIRS = 1 << 18
