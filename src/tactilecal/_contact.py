"""What counts as contact: the shares and widths the analysis, the report and the CLI share."""

__all__ = ["CONTACT_FORCE_SHARE", "DEFAULT_GAP_MM"]

CONTACT_FORCE_SHARE = 0.05
"""Share of the peak force above which a frame is in contact (steps), and below which the
centre of force is not drawn: with almost no load the centre is the mean of noise."""

DEFAULT_GAP_MM = 20.0
"""Loaded areas separated by less unloaded sensor than this are one contact (the toes and
the ball of a foot); areas farther apart, or on parts of the sensor that blank (NaN) sensels
separate (the two pads of a knee sensor), are separate contacts."""
