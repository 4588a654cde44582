# Spherical range maps (terrestrial laser scanners, LiDAR) from numpy: on a grid, or from points.
import numpy as np
import pytest

import levelfuse


def directions(azimuths_deg, elevations_deg):
    """Unit rays of a spherical scanner, a row per elevation and a column per azimuth, (H, W, 3)."""
    a = np.radians(azimuths_deg)[None, :]
    e = np.radians(elevations_deg)[:, None]
    return np.stack([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e) * np.ones_like(a)], axis=-1)


def sphere_ranges(rays, scanner, radius=1.0, inside=False):
    """Distances along the rays from `scanner` to the sphere of `radius` at the origin, NaN where they miss;
    from inside it, to its far side."""
    b = rays @ scanner
    c = scanner @ scanner - radius * radius
    disc = b * b - c
    root = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
    t = -b + root if inside else -b - root
    return np.where(t > 0.0, t, np.nan).astype(np.float32)


def translation(p):
    pose = np.eye(4)
    pose[:3, 3] = p
    return pose


def test_a_grid_of_ranges_is_a_spherical_map():
    ranges = np.full((41, 61), 5.0, dtype=np.float32)
    ranges[3, 4] = np.nan
    m = levelfuse.RangeMap.spherical(ranges, azimuth=(-30.0, 1.0), elevation=(-20.0, 1.0), pose=translation([1, 2, 3]),
                                     sigma=0.002, sigma_per_metre=0.0005, name="dome")
    assert m.kind == "spherical" and (m.width, m.height) == (61, 41)
    assert m.valid_count == 41 * 61 - 1
    assert m.scanner_position == pytest.approx((1.0, 2.0, 3.0))
    assert np.array_equal(m.readings(), ranges, equal_nan=True)
    with pytest.raises(ValueError):  # rows past the pole
        levelfuse.RangeMap.spherical(ranges, azimuth=(0.0, 1.0), elevation=(60.0, 1.0), pose=np.eye(4), sigma=0.002)
    with pytest.raises(TypeError):
        levelfuse.RangeMap.spherical(ranges.astype(np.float64), azimuth=(0.0, 1.0), elevation=(0.0, 1.0),
                                     pose=np.eye(4), sigma=0.002)


def test_scanners_points_reconstruct_a_ball_in_a_dome():
    # Four tripods around a ball of radius 1 inside a dome of radius 5, each sweeping a whole turn in 1-degree
    # steps: every ray returns, from the ball or from the dome behind it.
    rays = directions(np.arange(0.0, 360.0, 1.0), np.arange(-40.0, 40.5, 1.0))
    maps = []
    for scanner in ([3.0, 0.0, 0.4], [-3.0, 0.0, -0.4], [0.0, 3.0, 0.3], [0.0, -3.0, -0.3]):
        ball = sphere_ranges(rays, np.array(scanner))
        t = np.where(np.isnan(ball), sphere_ranges(rays, np.array(scanner), radius=5.0, inside=True), ball)
        m = levelfuse.RangeMap.from_points((rays * t[..., None]).reshape(-1, 3), azimuth_step=1.0,
                                           elevation_step=1.0, pose=translation(scanner), sigma=0.001)
        assert m.kind == "spherical"
        assert (m.width, m.height) == (361, 81)  # a whole turn closed: its first column again after its last
        assert m.valid_count == 361 * 81
        maps.append(m)
    result = levelfuse.reconstruct(maps, voxel_size=0.05)
    radii = np.linalg.norm(result.mesh().vertices, axis=1)
    ball = radii[radii < 2.5]
    assert len(ball) > 1000
    assert abs(ball.mean() - 1.0) < 0.01
    assert np.abs(ball - 1.0).max() < 0.05


def test_points_need_usable_steps():
    with pytest.raises(ValueError):
        levelfuse.RangeMap.from_points(np.ones((10, 3)), azimuth_step=0.0, elevation_step=1.0, pose=np.eye(4),
                                       sigma=0.001)
    with pytest.raises(ValueError):
        levelfuse.RangeMap.from_points(np.ones((10, 3)), azimuth_step=1.0, elevation_step=1.0, pose=np.eye(4),
                                       sigma=-1.0)


def test_uneven_rows_from_a_grid_or_from_points():
    # A LiDAR's lasers, a degree apart below the horizon and half a degree above, sweeping a wall 5 m away.
    lasers = np.array([-4.0, -3.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0])
    rays = directions(np.arange(-45.0, 45.5, 1.0), lasers)
    ranges = (5.0 / rays[..., 0]).astype(np.float32)
    m = levelfuse.RangeMap.spherical(ranges, azimuth=(-45.0, 1.0), elevation=lasers, pose=np.eye(4), sigma=0.002)
    assert (m.width, m.height) == (91, 8)
    assert m.row_elevations == pytest.approx(lasers)
    points = (rays * ranges[..., None]).reshape(-1, 3)
    binned = levelfuse.RangeMap.from_points(points, azimuth_step=1.0, elevation_step=lasers, pose=np.eye(4),
                                            sigma=0.002)
    assert (binned.width, binned.height) == (91, 8)
    assert binned.valid_count == 91 * 8  # each laser's points in its own row
    assert binned.row_elevations == pytest.approx(lasers)
    even = levelfuse.RangeMap.from_points(points, azimuth_step=1.0, elevation_step=0.5, pose=np.eye(4), sigma=0.002)
    assert even.height == 11 and even.row_elevations == []  # three empty rows between the lower lasers
    with pytest.raises(ValueError):  # not increasing
        levelfuse.RangeMap.spherical(ranges, azimuth=(-45.0, 1.0), elevation=lasers[::-1].copy(), pose=np.eye(4),
                                     sigma=0.002)
    with pytest.raises(ValueError):  # not one per row
        levelfuse.RangeMap.spherical(ranges, azimuth=(-45.0, 1.0), elevation=lasers[:5], pose=np.eye(4),
                                     sigma=0.002)
