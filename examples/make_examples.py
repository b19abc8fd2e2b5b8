"""Regenerate the example inputs from the bundled prior's own samples (no third-party data).

    python examples/make_examples.py

Writes examples/prior_samples_coco.json: 6 poses sampled from the bundled syrip12 prior (seed 7),
placed 1.6 m in front of the paper's pseudo camera (f = 2000 px at the centre of a 1280x720
image) and projected to COCO-17 keypoints; joints that syrip12 lacks (face) are v = 0, and one
wrist is marked missing (v = 0) to show how zedo fills and flags missing joints.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch

from zedo_cli.data.skeleton import center_on_root, get_skeleton
from zedo_cli.lifting.camera import Intrinsics, project
from zedo_cli.prior.sampling import sample_poses
from zedo_cli.prior.weights import bundled_prior_path, load_prior

OUT = Path(__file__).with_name("prior_samples_coco.json")
WIDTH, HEIGHT, DEPTH_M = 1280, 720, 1.6


def main() -> None:
    prior = load_prior(bundled_prior_path())
    poses = sample_poses(prior.model, prior.sde, (6, 12, 3), generator=torch.Generator().manual_seed(7))
    poses = center_on_root(poses.double().numpy(), prior.skeleton)
    k = Intrinsics.pseudo(WIDTH, HEIGHT).matrix()
    xy = project(torch.tensor(poses + np.array([0.0, 0.0, DEPTH_M])), torch.tensor(k)).numpy()
    coco = get_skeleton("coco17")
    columns = [coco.index(j) for j in prior.skeleton.joints]
    images, annotations = [], []
    for i, pts in enumerate(xy):
        kp = np.zeros((17, 3))
        kp[columns, :2] = pts.round(2)
        kp[columns, 2] = 2
        if i == 1:
            kp[coco.index("left_wrist")] = 0  # a missing joint: the prior fills it
        images.append({"id": i + 1, "file_name": f"sample{i + 1}.jpg", "width": WIDTH, "height": HEIGHT})
        annotations.append({"id": i + 1, "image_id": i + 1, "category_id": 1, "keypoints": kp.ravel().tolist(),
                            "num_keypoints": int((kp[:, 2] > 0).sum())})  # fmt: skip
    categories = [{"id": 1, "name": "person", "keypoints": list(coco.joints), "skeleton": []}]
    doc = {"info": {"description": "zedo example: projections of samples of the bundled syrip12 prior "
                    "(seed 7, depth 1.6 m, f 2000 px); see examples/README.md"},
           "images": images, "annotations": annotations, "categories": categories}  # fmt: skip
    OUT.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
