"""Measures of one pose or frame: the vector helpers (`geometry`), postural symmetry (`symmetry`), joint
angles in a trunk frame (`joint_angles`), and the head's tilt and turn from the input's 2D with its clip
shares (`head`).

Imports from `analysis.uncertainty` only, within the analysis (docs/ARCHITECTURE.md).
"""
