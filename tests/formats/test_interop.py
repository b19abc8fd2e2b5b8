"""The exports read by the real tools: OpenSim's Python package (`TimeSeriesTableVec3`,
`MarkerData`) and Pose2Sim's `read_trc` read the TRC; the `c3d` library reads the C3D.

OpenSim and Pose2Sim are heavy: these tests are opt-in (`pytest -m interop`, with the `interop`
extra; docs/exports.md) and skip when the package is absent. The `c3d` reader runs by default."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from export_fixtures import EMPTY, FPS, FRAMES, UNLIFTED, json_markers, lift_clip

from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.formats.writers.markers import marker_name

POSE2SIM_COCO = "RHip LHip RKnee LKnee RAnkle LAnkle RShoulder LShoulder RElbow LElbow RWrist LWrist".split()
MARKERS = [marker_name(j) for j in get_skeleton("syrip12").joints]  # in the skeleton's order
assert sorted(MARKERS) == sorted(POSE2SIM_COCO)


@pytest.fixture(autouse=True)
def _temporary_cwd(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """OpenSim writes `opensim.log` into the working directory when it loads (and Pose2Sim imports
    it): each test runs in its own temporary folder, so nothing lands in the checkout."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture(scope="module")
def clip(tiny_prior_path: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return lift_clip(tiny_prior_path, tmp_path_factory.mktemp("interop"))


def test_c3d_library_reads_missing_points_as_invalid(clip: dict[str, Path]) -> None:
    import c3d

    expected = json_markers(clip["json"]) * 1000.0
    with open(clip["c3d"], "rb") as fh, warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # "no analog data": none is written
        reader = c3d.Reader(fh)
        assert [label.strip() for label in reader.point_labels] == MARKERS
        assert reader.point_rate == FPS and reader.get("POINT:UNITS").string_value.strip() == "mm"
        frames = [points for _, points, _ in reader.read_frames()]
    assert len(frames) == FRAMES
    for f, points in enumerate(frames):
        valid = points[:, 3] >= 0
        np.testing.assert_array_equal(valid, np.isfinite(expected[f]).all(-1))
        np.testing.assert_allclose(points[valid, :3], expected[f][valid], atol=0.1)


@pytest.mark.interop
def test_opensim_reads_the_trc(clip: dict[str, Path]) -> None:
    opensim = pytest.importorskip("opensim")
    table = opensim.TimeSeriesTableVec3(str(clip["trc"]))
    assert table.getNumRows() == FRAMES and table.getNumColumns() == 12
    assert list(table.getColumnLabels()) == MARKERS
    assert table.getTableMetaDataAsString("Units") == "m" and float(table.getTableMetaDataAsString("DataRate")) == FPS
    times = np.array(table.getIndependentColumn())
    np.testing.assert_allclose(times, np.arange(FRAMES) / FPS, atol=1e-6)
    expected = json_markers(clip["json"])
    got = np.array([[[table.getRowAtIndex(f)[m][k] for k in range(3)] for m in range(12)] for f in range(FRAMES)])
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    np.testing.assert_allclose(got, expected, atol=1e-4, equal_nan=True)
    markers = opensim.MarkerData(str(clip["trc"]))
    assert markers.getNumFrames() == FRAMES and markers.getDataRate() == FPS
    assert markers.getUnits().getAbbreviation() == "m" and markers.getMarkerNames().getSize() == 12
    assert math.isnan(markers.getFrame(EMPTY).getMarker(0).get(0))


@pytest.mark.interop
def test_pose2sim_reads_the_trc(clip: dict[str, Path]) -> None:
    common = pytest.importorskip("Pose2Sim.common")
    data, frames, times, markers, _ = common.read_trc(str(clip["trc"]))
    assert markers == MARKERS
    assert data.shape == (FRAMES, 36) and frames.tolist() == list(range(1, FRAMES + 1))
    np.testing.assert_allclose(times.to_numpy(), np.arange(FRAMES) / FPS, atol=1e-6)
    got = data.to_numpy(dtype=float).reshape(FRAMES, 12, 3)
    expected = json_markers(clip["json"])
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    assert np.isnan(got[[EMPTY, UNLIFTED]]).all()
    np.testing.assert_allclose(got, expected, atol=1e-4, equal_nan=True)
