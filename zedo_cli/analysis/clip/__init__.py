"""Features of a person's clip: movement of joint-angle series (`movement`), the published 2D features of
Chambers et al. 2020 (`published_features`, on the pandas-1.x steps of `series`), the `3d_` features of the
lifted poses (`features_3d`), gathered and calibrated per track (`clip_features`).

Imports from `analysis.uncertainty` and `analysis.pose` only, within the analysis (docs/ARCHITECTURE.md).
"""
