"""Defaults of the analysis that several of its modules share (one place each)."""

__all__ = ["CONTACT_FORCE_SHARE"]

CONTACT_FORCE_SHARE = 0.05
"""Share of the peak force above which a frame is in contact (steps), and below which the
centre of force is not drawn: with almost no load the centre is the mean of noise."""
