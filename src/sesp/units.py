"""Units of the quantities in sesp's datasets, in a form CF tools read correctly.

Lengths are reduced by b, the superellipse's semi-axis along y (DESIGN.md):
x = 1.5 means 1.5 b. A reduced length is a pure number, so its CF ``units``
is "1" (UDUNITS, and so cf-xarray and pint, would read "b" as the barn,
1e-28 m²); ``in_units_of`` says which power of b it was reduced by, and
``long_name`` says so in words where a label is drawn from it.
"""

__all__ = ["LENGTH", "AREA", "DENSITY", "reduced"]

LENGTH = {"units": "1", "in_units_of": "b"}
AREA = {"units": "1", "in_units_of": "b^2"}
DENSITY = {"units": "1", "in_units_of": "b^-2"}


def reduced(power: int) -> dict:
    """The attributes of a quantity in units of b**power (power 0: a pure number)."""
    return {0: {"units": "1"}, 1: LENGTH, 2: AREA, -2: DENSITY}[power]
