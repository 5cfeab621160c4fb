"""The renderer's colours (RGB tuples) and palettes (uint8 arrays), shared by the frame and
its legend."""

import numpy as np

# --- colours (RGB) ---------------------------------------------------------------------------
OUTSIDE = (70, 70, 74)  # beyond the arena walls (padding / letterbox)
FLOOR = (250, 250, 246)
WALL = (30, 30, 34)
TARGET_FILL = (224, 233, 247)
TARGET_EDGE = (60, 100, 165)
OBSTACLE_FILL = (120, 120, 126)
OBSTACLE_EDGE = (60, 60, 66)
SPAWN_EDGE = (185, 185, 185)
BEACON_FILL = (255, 205, 0)
BEACON_EDGE = (170, 100, 0)
COVER_FILL = (182, 208, 242)  # covered target pixels: a deeper tint of TARGET_FILL
COLORKEY = (255, 0, 255)
FAILED = (20, 20, 20)
FAILED_MARK = (210, 210, 210)
LEADER_RING = (0, 0, 0)
CONTACT_RING = (230, 0, 0)
HEADING_MARK = (45, 45, 45)  # the line from a robot's centre toward its heading
NONE_GREY = (150, 150, 150)
TEXT = (20, 20, 20)
PANEL = (255, 255, 255, 215)

GRADIENT_PALETTE = np.array([
    (228, 26, 28), (255, 127, 0), (225, 185, 0), (150, 200, 30), (50, 160, 45),
    (0, 150, 120), (0, 185, 210), (30, 120, 220), (50, 60, 190), (120, 70, 200),
    (170, 40, 170), (230, 60, 150), (150, 90, 50), (105, 105, 35),
], dtype=np.uint8)
"""The 14-colour cycle for hop gradients (colour = gradient % 14), as in the paper's figures."""

GROUP_PALETTE = np.array([
    (31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (188, 189, 34), (23, 190, 207), (0, 0, 128),
], dtype=np.uint8)
"""Categorical colours for groups 1, 2, ... (cycled); group 0 (none) is grey."""

STATUS_PALETTE = np.vstack([GROUP_PALETTE, np.array([(0, 128, 128), (128, 128, 128)],
                                                     dtype=np.uint8)])
"""Colours for status codes 0, 1, ... (cycled): the group colours, then teal and grey."""
