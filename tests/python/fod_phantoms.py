"""A crossing of two fibre bundles made by DIPY: the FOD tests' phantom
(test_fod.py through stvd's reader, test_fod_distance.py through the
package)."""

import warnings

import numpy as np

from dipy.core.gradients import gradient_table
from dipy.data import get_sphere
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel
from dipy.sims.voxel import multi_tensor


def crossing_fit(angle):
    """A 21 x 21 x 3 phantom of 2 mm voxels: bundle 0 along the voxel axis i
    through j = 10, bundle 1 at `angle` to it in the i-j plane through the
    centre, each 5 voxels wide, DIPY's multi_tensor signal (b = 3000, 100
    directions, no noise) fitted by DIPY's CSD (lmax 8) inside the bundles.
    Returns the fit, the bundles' axes (voxel frame) and in_bundle(b, i, j),
    whether voxel (i, j, .) lies in bundle b."""
    sphere = get_sphere("repulsion100")
    gtab = gradient_table(np.r_[0.0, np.full(100, 3000.0)], np.r_[np.zeros((1, 3)), sphere.vertices])
    evals = np.array([0.0017, 0.0002, 0.0002])
    axes = [np.array([1.0, 0.0, 0.0]), np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])]

    def in_bundle(b, i, j):
        x = np.array([i - 10.0, j - 10.0, 0.0])
        return np.linalg.norm(x - (x @ axes[b]) * axes[b]) <= 2 + 1e-9

    signals = {}
    for key, angles in (((0,), [(90, 0), (90, 0)]), ((1,), [(90, angle), (90, angle)]),
                        ((0, 1), [(90, 0), (90, angle)])):
        signals[key], _ = multi_tensor(gtab, np.array([evals, evals]), S0=100, angles=angles, fractions=[50, 50],
                                       snr=None)
    data = np.zeros((21, 21, 3, 101))
    mask = np.zeros((21, 21, 3), bool)
    for i in range(21):
        for j in range(21):
            key = tuple(b for b in (0, 1) if in_bundle(b, i, j))
            if key:
                data[i, j, :] = signals[key]
                mask[i, j, :] = True
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ConstrainedSphericalDeconvModel(gtab, (evals, 100.0), sh_order=8).fit(data, mask=mask)
    return fit, axes, in_bundle
