"""A wide lens with barrel distortion: how much does lifting through its calibration file win back?
(docs/cameras.md "Benchmark")

SyRIP's Test100 weak-ground-truth 3D poses are placed in front of a camera with f = 600 px,
k1 = -0.3, k2 = 0.1 on a 1280 x 720 image, off-centre (root point at x = 0.3 m, 1 m deep, where
the lens bends limbs most), projected through the lens with OpenCV and lifted with the default
preset and the bundled prior:

  (a) with the camera's OpenCV FileStorage YAML file (written by cv2.FileStorage),
  (b) with the same camera in a Pose2Sim Calib.toml file (picked by name among two cameras),
  (c) ignoring the distortion (the file's K alone, the 2D as the lens bent it),
  (d) the same poses projected through the pinhole camera of the same K and lifted through it:
      what (a) and (b) should reach.

Reported per case: MPJPE of the root-relative poses (mm), the root point's error (mm, mean and
median), the mean reprojection error in the image lifted from (px) and the poses lifted. Nothing
is chosen from Test100: every setting is the default.

    nice -n 10 python benchmarks/accuracy/wide_lens.py --syrip-dir ../shared/data/syrip [--out wide_lens.json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from zedo_cli.camera.model import CameraModel

LENS = CameraModel(600.0, 600.0, 640.0, 360.0, (-0.3, 0.1, 0.0, 0.0, 0.0), image_size=(1280, 720))
ROOT = np.array([0.3, 0.0, 1.0])  # metres, camera frame


def write_opencv_yaml(path: Path, camera: CameraModel) -> None:
    """The camera as OpenCV's calibration sample writes it, by cv2.FileStorage itself."""
    import cv2

    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("image_width", camera.image_size[0])
    storage.write("image_height", camera.image_size[1])
    storage.write("camera_matrix", camera.matrix())
    storage.write("distortion_coefficients", np.asarray(camera.dist, dtype=np.float64).reshape(1, -1))
    storage.release()


def write_pose2sim_toml(path: Path, camera: CameraModel) -> None:
    """Pose2Sim's Calib.toml layout: one table per camera (name, size, matrix, distortions
    k1 k2 p1 p2, rotation, translation, fisheye) and a metadata table; two cameras here."""

    def table(key: str, name: str, cam: CameraModel) -> str:
        k = cam.matrix()
        rows = ", ".join("[ " + ", ".join(f"{v!r}" for v in row) + "]" for row in k.tolist())
        return (
            f'[{key}]\nname = "{name}"\nsize = [ {cam.image_size[0]:.1f}, {cam.image_size[1]:.1f}]\n'
            f"matrix = [ {rows}]\ndistortions = [ {', '.join(repr(c) for c in cam.dist[:4])}]\n"
            "rotation = [ 1.2, -0.1, 0.3]\ntranslation = [ 0.5, 0.2, 2.1]\nfisheye = false\n\n"
        )

    other = CameraModel(1400.0, 1400.0, 960.0, 540.0, (0.01, -0.02, 0.0, 0.0), image_size=(1920, 1080))
    text = table("cam_01", "side", other) + table("cam_02", "wide", camera)
    path.write_text(text + "[metadata]\nadjusted = false\nerror = 0.0\n", encoding="utf-8")


def lift_case(prior, xy: np.ndarray, calibration: str | None, camera: str | None, ignore_lens: bool = False) -> dict:
    """Lift `xy` through the camera of `calibration` (its lens unless `ignore_lens`)."""
    from zedo_cli import get_preset, lift
    from zedo_cli.lifting.camera import resolve_cameras

    n = len(xy)
    sizes = np.tile([1280.0, 720.0], (n, 1))
    cams = resolve_cameras(sizes, list(range(n)), [None] * n, intrinsics_file=calibration, camera=camera,
                           focal=LENS.fx)  # fmt: skip
    lenses = None if ignore_lens else cams.lenses
    start = time.perf_counter()
    res = lift(xy, np.ones(xy.shape[:2]), cams.matrices, prior, get_preset("fast"), cameras=lenses)
    return {"res": res, "seconds": time.perf_counter() - start}


def score(res, truth: np.ndarray) -> dict[str, float]:
    from zedo_cli.evaluation.metrics import mpjpe_mm

    ok = res.lifted
    root_err = np.linalg.norm(res.root_translation[ok] - ROOT, axis=-1) * 1000
    return {
        "lifted": int(ok.sum()),
        "mpjpe_mm": round(mpjpe_mm(res.poses_root_relative[ok], truth[ok]), 2),
        "root_mean_mm": round(float(root_err.mean()), 1),
        "root_median_mm": round(float(np.median(root_err)), 1),
        "reprojection_px": round(float(np.nanmean(res.reprojection_error_px[ok])), 2),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--syrip-dir", required=True)
    parser.add_argument("--prior", default=None, help="a bundled prior's name or a weights file (default: bundled)")
    parser.add_argument("--out", default=None, help="also write the figures as JSON here")
    args = parser.parse_args()

    from zedo_cli import load_prior, load_syrip_3d, resolve_prior_path

    truth = load_syrip_3d(args.syrip_dir, "test").poses  # (100, J, 3) root-relative metres
    points = truth + ROOT
    pinhole = CameraModel(LENS.fx, LENS.fy, LENS.cx, LENS.cy, image_size=LENS.image_size)
    seen, ideal = LENS.project(points), pinhole.project(points)
    bend = np.linalg.norm(seen - ideal, axis=-1)
    prior = load_prior(resolve_prior_path(args.prior))
    with tempfile.TemporaryDirectory() as tmp:
        yaml, toml = Path(tmp) / "camera.yml", Path(tmp) / "Calib.toml"
        write_opencv_yaml(yaml, LENS)
        write_pose2sim_toml(toml, LENS)
        header = yaml.read_text().splitlines()[0]
        cases = {
            "a_opencv_yaml": lift_case(prior, seen, str(yaml), None),
            "b_pose2sim_toml": lift_case(prior, seen, str(toml), "wide"),
            "c_distortion_ignored": lift_case(prior, seen, str(yaml), None, ignore_lens=True),
            "d_pinhole_reference": lift_case(prior, ideal, None, None),
        }
    table = {name: {**score(c["res"], truth), "seconds": round(c["seconds"], 2)} for name, c in cases.items()}
    ref = table["d_pinhole_reference"]
    for row in table.values():
        row["mpjpe_minus_d_mm"] = round(row["mpjpe_mm"] - ref["mpjpe_mm"], 2)
        row["root_mean_minus_d_mm"] = round(row["root_mean_mm"] - ref["root_mean_mm"], 1)
    report = {
        "poses": len(truth),
        "lens": LENS.to_json(),
        "root_m": ROOT.tolist(),
        "opencv_yaml_header": header,
        "lens_bend_px": {"mean": round(float(bend.mean()), 1), "max": round(float(bend.max()), 1)},
        "cases": table,
    }
    print(f"{len(truth)} Test100 poses, root at {ROOT.tolist()} m; the lens moves joints {bend.mean():.1f} px "
          f"(mean), {bend.max():.1f} px (max); OpenCV wrote {header!r}")  # fmt: skip
    print(f"{'case':22} {'lifted':>6} {'MPJPE mm':>9} {'- (d)':>6} {'root mean':>9} {'- (d)':>6} "
          f"{'root median':>11} {'reproj px':>9} {'s':>6}")  # fmt: skip
    for name, r in table.items():
        print(f"{name:22} {r['lifted']:>6} {r['mpjpe_mm']:>9.2f} {r['mpjpe_minus_d_mm']:>6.2f} "
              f"{r['root_mean_mm']:>9.1f} {r['root_mean_minus_d_mm']:>6.1f} {r['root_median_mm']:>11.1f} "
              f"{r['reprojection_px']:>9.2f} {r['seconds']:>6.1f}")  # fmt: skip
    if args.out:
        Path(args.out).write_text(json.dumps(report, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
