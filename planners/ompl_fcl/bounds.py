"""Oriented bounding boxes and the separating-axis test that culls solid
pairs before fcl's narrow phase, batched in numpy.

A box is a pose (4x4, its centre and axes) and half extents (3,).  The test
is exact for boxes (Ericson, Real-Time Collision Detection, 4.4.1): it
proves two boxes apart or lets the pair through, so culling never hides a
contact of the solids inside.
"""

from __future__ import annotations

import numpy as np

# the nine axes A_i x B_j: i, j and their two cyclic successors
_I = np.repeat(np.arange(3), 3)
_J = np.tile(np.arange(3), 3)
_I1, _I2, _J1, _J2 = (_I + 1) % 3, (_I + 2) % 3, (_J + 1) % 3, (_J + 2) % 3
_SLACK = 1e-9  # against parallel edges whose cross product vanishes


def axes_overlap(pose_a: np.ndarray, half_a: np.ndarray, pose_b: np.ndarray,
                 half_b: np.ndarray) -> np.ndarray:
    """The separating-axis test on (n, 4, 4) poses and (n, 3) half extents:
    true for the pairs of boxes that no axis proves apart."""
    rot_a_t = np.swapaxes(pose_a[:, :3, :3], 1, 2)
    r = rot_a_t @ pose_b[:, :3, :3]  # r[i, j] = A_i . B_j
    t = (rot_a_t @ (pose_b[:, :3, 3] - pose_a[:, :3, 3])[:, :, None])[:, :, 0]  # in A's frame
    abs_r = np.abs(r) + _SLACK
    apart = np.any(np.abs(t) > half_a + (abs_r @ half_b[:, :, None])[:, :, 0], axis=1)
    t_b = (t[:, None, :] @ r)[:, 0]
    apart |= np.any(np.abs(t_b) > (half_a[:, None, :] @ abs_r)[:, 0] + half_b, axis=1)
    ra = half_a[:, _I1] * abs_r[:, _I2, _J] + half_a[:, _I2] * abs_r[:, _I1, _J]
    rb = half_b[:, _J1] * abs_r[:, _I, _J2] + half_b[:, _J2] * abs_r[:, _I, _J1]
    d = np.abs(t[:, _I2] * r[:, _I1, _J] - t[:, _I1] * r[:, _I2, _J])
    apart |= np.any(d > ra + rb, axis=1)
    return ~apart
