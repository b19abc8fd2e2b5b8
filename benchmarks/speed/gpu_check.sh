#!/usr/bin/env bash
# The GPU figures of docs/benchmarks.md, in one go on a machine with a CUDA GPU (about 6 minutes on an H100, 8 at most):
#
#   1. `zedo benchmark --scale 100000 --scale 1000000 --device cuda`: lift throughput (poses/s, as zedo
#      reports it) and peak GPU memory (torch.cuda.max_memory_allocated) of 10^5 and 10^6 synthetic
#      poses, `fast`, the default chunk of 4096 rows; the first 10^5 poses lifted on the CPU too and
#      compared pose by pose (share within 1 mm and 10 mm, the rest by class); 200 epochs of the
#      bundled prior's recipe timed on the GPU and extrapolated to its 8000 (an estimate).
#   2. The same 10^6 poses with --chunk-size 65536, throughput only: whether larger chunks pay on a GPU.
#
# Run from the repository root:  bash benchmarks/speed/gpu_check.sh
# Environment: PYTHON (default: python; needs torch with CUDA and zedo's dependencies), SYRIP_DIR (the
# SyRIP folder: its 600 training poses are the pose source; default ../shared/data/syrip, else poses
# sampled from the prior), OUT (a folder: the JSON reports are written there; default the current folder).
# Exit status: the first run's (2: no CUDA GPU, the one-line refusal).
set -u
PYTHON=${PYTHON:-python}
OUT=${OUT:-.}
SYRIP_DIR=${SYRIP_DIR:-../shared/data/syrip}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)  # the repository root: its zedo_cli is the one timed
export PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}"
mkdir -p "$OUT"
source_args=()
[ -d "$SYRIP_DIR" ] && source_args=(--syrip-dir "$SYRIP_DIR")
"$PYTHON" -c "import torch; print('torch', torch.__version__, 'cuda', torch.cuda.is_available(), \
torch.cuda.get_device_name(0) if torch.cuda.is_available() else '')" | tee "$OUT/gpu_check_env.txt"
nproc | tee -a "$OUT/gpu_check_env.txt"
start=$(date +%s)
timeout 390 "$PYTHON" -m zedo_cli benchmark --scale 100000 --scale 1000000 --device cuda \
    --agreement-poses 100000 --fit-epochs 200 "${source_args[@]}" \
    -o "$OUT/gpu_check.json" --overwrite 2> >(tee "$OUT/gpu_check.log" >&2)
status=$?
left=$((470 - ($(date +%s) - start)))
if [ "$status" -eq 0 ] && [ "$left" -gt 60 ]; then
    timeout "$left" "$PYTHON" -m zedo_cli benchmark --scale 1000000 --device cuda --chunk-size 65536 \
        --agreement-poses 0 --fit-epochs 0 "${source_args[@]}" \
        -o "$OUT/gpu_check_chunk65536.json" --overwrite 2> >(tee "$OUT/gpu_check_chunk65536.log" >&2)
fi
exit "$status"
