"""Rotating multi-beam LiDAR models: beam elevations, firing order and timing.

Firing order matters because it is what real drivers emit: a VLP-16 fires its lasers in the
interleaved order -15, +1, -13, +3, ... deg, each 2.304 us apart, 16 firings per 55.296 us
block (velodyne "VLP-16 User Manual", firing timing). The head turns during a block, so each
ring has its own small azimuth offset, which the core must handle. `ring` is the index by
elevation, 0 = lowest, as velodyne_pointcloud numbers it. The head turns clockwise seen from
above (azimuth decreasing), as in the real bags (rosbag_fixtures/, ../shared/data/real).
"""
from dataclasses import dataclass

import numpy as np


@dataclass
class Sensor:
    name: str
    elevation_deg: np.ndarray   # per laser id, in firing order
    firing_dt: float            # [s] between two lasers of a block (0 = simultaneous)
    block_period: float         # [s] between two columns (firing blocks)
    rpm: float
    max_range: float
    min_range: float
    organized: bool             # organized output: height = beams, width = columns, NaN no-returns

    @property
    def n_beams(self):
        return len(self.elevation_deg)

    @property
    def ring(self):
        """Ring number of each laser id: rank by elevation, 0 = lowest."""
        return np.argsort(np.argsort(self.elevation_deg, kind="stable"), kind="stable")

    @property
    def n_columns(self):
        return int(round(60.0 / self.rpm / self.block_period))

    @property
    def azimuth_step_deg(self):
        return 360.0 * self.rpm / 60.0 * self.block_period


def _interleaved(low_to_high):
    """Firing order that alternates between the lower and upper half of the beams."""
    n = len(low_to_high)
    half = n // 2
    order = np.empty(n)
    order[0::2] = low_to_high[:half]
    order[1::2] = low_to_high[half:]
    return order


def make_sensor(name):
    if name == "vlp16":
        # laser j: -15 + j deg for even j, +j deg for odd j (-15, 1, -13, 3, ... 13, -1, 15)
        j = np.arange(16)
        elev = np.where(j % 2 == 0, -15.0 + j, j.astype(float))
        return Sensor("vlp16", elev, 2.304e-6, 55.296e-6, 600.0, 100.0, 0.4, False)
    if name == "hdl32":
        # HDL-32E: -30.67 .. +10.67 deg in 4/3 deg steps, fired -30.67, -9.33, -29.33, -8.00, ...
        elev = _interleaved(np.linspace(-30.67, 10.67, 32))
        return Sensor("hdl32", elev, 1.152e-6, 46.08e-6, 600.0, 100.0, 0.4, False)
    if name == "hdl64":
        # HDL-64E-like (KITTI): -24.9 .. +2.0 deg, evenly spaced here, 0.18 deg columns
        elev = _interleaved(np.linspace(-24.9, 2.0, 64))
        return Sensor("hdl64", elev, 0.78e-6, 50.0e-6, 600.0, 120.0, 0.9, False)
    if name == "os128":
        # OS1-128-like: +-22.5 deg, 1024 columns at 10 Hz, all beams of a column fire together;
        # organized 128 x 1024 with NaN where there is no return, as ouster-ros publishes it.
        elev = np.linspace(-22.5, 22.5, 128)
        return Sensor("os128", elev, 0.0, 0.1 / 1024, 600.0, 120.0, 0.3, True)
    raise ValueError("unknown sensor '%s' (vlp16, hdl32, hdl64, os128)" % name)


SENSORS = ("vlp16", "hdl32", "hdl64", "os128")
