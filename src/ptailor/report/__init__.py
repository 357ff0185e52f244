"""Distortion metrics and the adjustment report."""
