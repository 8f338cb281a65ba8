"""The joints' components in the verdict, as seed 000's final (v2) joints build them
(docs/components.md): the screws that clamp each plate to its rail, the shafts, the
bearings and the carriages, each checked analytically by its standard
(:mod:`~railcheck.components.standards`) from the joint force histories the
kinematics give (:mod:`~railcheck.components.checks`; a check's cycle:
:mod:`~railcheck.components.scene_checks`), with every dimension and rating from seed 000,
a cited catalogue, or marked "assumed" (:mod:`~railcheck.components.ratings`).

A scene runs the components its ``[check] parts`` lists (none listed: none run); the
``[components]`` table overrides any dimension or rating. This package's top stays light
(the scene reader imports the ratings).
"""
