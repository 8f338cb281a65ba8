"""Labels beside what they name (railcheck.report.labels): never over another label or a
marked point, inside the picture; and linkage.png, whose joints' and bars' labels obey it
for a four-bar and a slider-crank."""

import numpy as np
import pytest

from railcheck.api import scene_of
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.report.labels import Box, box_at, conflicts_among, place_labels
from railcheck.report.linkage_picture import write_linkage_picture

PICTURE = Box(0.0, 0.0, 800.0, 500.0)


def test_crowded_labels_are_placed_apart_and_off_their_points():
    rng = np.random.default_rng(3)
    anchors = np.array([400.0, 250.0]) + rng.normal(0.0, 25.0, (10, 2))  # ten points within a few label sizes
    sizes = [(70.0, 18.0)] * 10
    points = np.column_stack([anchors, np.full(10, 8.0)])
    boxes = place_labels(anchors, sizes, points, PICTURE)
    assert conflicts_among(boxes, points, PICTURE) == []
    naive = [box_at(tuple(a), s) for a, s in zip(anchors, sizes)]  # each label on its point: what the test catches
    assert any("overlap" in p for p in conflicts_among(naive, points, PICTURE))
    assert any("covers" in p for p in conflicts_among(naive, points, PICTURE))


def test_a_label_keeps_out_of_the_drawing_and_stays_in_the_picture():
    part = Box(100.0, 200.0, 700.0, 300.0)  # a rail across the picture
    anchors = np.array([[150.0, 250.0], [400.0, 250.0], [650.0, 250.0], [790.0, 250.0]])
    boxes = place_labels(anchors, [(90.0, 20.0)] * 4, np.zeros((0, 3)), PICTURE, keep_out=[part])
    assert not any(b.overlaps(part) for b in boxes) and conflicts_among(boxes, np.zeros((0, 3)), PICTURE) == []


@pytest.mark.parametrize(
    "scene", [None, '[mechanism]\nkind = "slider-crank"\ncrank = "300 mm"\ncoupler = "900 mm"\n'], ids=["four-bar", "slider"]
)
def test_the_linkage_picture_labels_every_joint_off_the_joints(tmp_path, scene):
    k = run_kinematics(kinematics_input(scene_of(scene)))
    boxes, joints, area = write_linkage_picture(tmp_path / "linkage.png", k.motion, k.dynamics)
    assert (tmp_path / "linkage.png").stat().st_size > 10_000
    assert len(boxes) == len(k.motion.points) + (4 if "O4" in k.motion.points else 2)  # joints; bars and ground
    assert conflicts_among(boxes, joints, area) == []
