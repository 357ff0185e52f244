"""The method: intrinsic scale targets (section 2 of DESIGN.md) and the stitching solver."""
