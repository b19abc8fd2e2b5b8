"""The colours of the body's sides in every figure zedo draws: `zedo render`'s overlay (OpenCV, BGR),
the HTML report of `zedo analyze`, the pose plots of `zedo lift --plot` and `zedo augment`'s check
figures (matplotlib, hex). One definition, so that a person's left limbs are the same blue and the
right ones the same orange wherever they are looked at (a colour-blind-safe pair).

The bones between the sides (hip to hip, shoulder to shoulder) differ by background only: yellow
over footage, grey on a white page.
"""

from __future__ import annotations

RGB = tuple[int, int, int]

LEFT_RGB: RGB = (40, 160, 255)  # blue: the person's own left (joint names left_*)
RIGHT_RGB: RGB = (255, 110, 40)  # orange: the person's own right (right_*)
CENTRE_ON_FOOTAGE_RGB: RGB = (230, 230, 90)  # yellow, seen on any video
CENTRE_ON_PAGE_RGB: RGB = (89, 89, 89)  # grey, on a white page


def bgr(rgb: RGB) -> RGB:
    """OpenCV's channel order."""
    return rgb[2], rgb[1], rgb[0]


def hex_colour(rgb: RGB) -> str:
    """`#rrggbb`, for matplotlib and CSS."""
    return "#{:02x}{:02x}{:02x}".format(*rgb)


LEFT_HEX, RIGHT_HEX, CENTRE_HEX = hex_colour(LEFT_RGB), hex_colour(RIGHT_RGB), hex_colour(CENTRE_ON_PAGE_RGB)


def side_of(name: str) -> str:
    """ "left", "right" or "centre" of a joint name."""
    return "left" if name.startswith("left_") else "right" if name.startswith("right_") else "centre"


def side_hex(*names: str) -> str:
    """The page colour of a joint, or of a bone (its two joints' names): left or right when every
    name is on that side, else centre."""
    sides = {side_of(n) for n in names}
    if sides == {"left"}:
        return LEFT_HEX
    if sides == {"right"}:
        return RIGHT_HEX
    return CENTRE_HEX
