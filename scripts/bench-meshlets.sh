#!/usr/bin/env bash
# Paper C's measurements on a GPU machine: the extraction scenario (meshlets against PMB at
# every block size), the iso-sweep scenario (a new isovalue every
# frame: extraction + draw for meshlets, against direct and ray marching) and the isosurface
# scenario (fixed isovalue, offline meshlets drawn beside them) at 3840x2160; then GPU meshlet
# extraction (`tessera extract`, GPU timestamps) against scikit-image's marching_cubes on the
# same arrays. JSON lines and a summary go to OUT_DIR.
# Usage: scripts/bench-meshlets.sh OUT_DIR [TESSERA_BINARY]
# PARTS (default "iso-sweep extraction isosurface skimage") picks the parts to run;
# EXTRACTION_VOLUMES and SWEEP_VOLUMES override the volume lists; EXTRACTION_PATHS (e.g.
# compute) limits the extraction scenario's paths.
set -uo pipefail
parts=" ${PARTS:-iso-sweep extraction isosurface skimage} "
sweep_volumes=${SWEEP_VOLUMES:-procedural:head:256:u8 procedural:turbulence:512:f32 procedural:head:512:u16}
extraction_volumes=${EXTRACTION_VOLUMES:-procedural:head:256:u8 procedural:turbulence:512:f32 procedural:head:512:u16 procedural:head:1024:u16 procedural:head:1024x1024x1080:u16 procedural:head:1024x1024x1546:u16}
out=${1:?output folder}
bin=${2:-target/release/tessera}
mkdir -p "$out"
if ! "$bin" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$bin" info > "$out/info.txt" 2>&1
nvidia-smi --query-gpu=name,driver_version --format=csv > "$out/nvidia-smi.csv" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ > "$out/date.txt"
common=(--sizes 3840x2160 --frames 30 --warmup 20 --iso-fraction 0.3)
for volume in $sweep_volumes; do
  [[ $parts == *" iso-sweep "* ]] || break
  echo "== iso-sweep $volume"
  timeout 240 "$bin" bench iso-sweep --data "$volume" "${common[@]}" --json "$out/iso-sweep.jsonl" \
    > "$out/iso-sweep-${volume//[:\/]/_}.txt" 2>&1 || echo "iso-sweep $volume failed: $?"
done
for volume in $extraction_volumes; do
  [[ $parts == *" extraction "* ]] || break
  echo "== extraction $volume"
  timeout 300 "$bin" bench extraction --data "$volume" --frames 30 --warmup 10 --iso-fraction 0.3 \
    ${EXTRACTION_PATHS:+--paths "$EXTRACTION_PATHS"} \
    --json "$out/extraction.jsonl" > "$out/extraction-${volume//[:\/]/_}.txt" 2>&1 || echo "extraction $volume failed: $?"
done
if [[ $parts == *" isosurface "* ]]; then
  echo "== isosurface procedural:head:256:u8"
  timeout 180 "$bin" bench isosurface --data procedural:head:256:u8 "${common[@]}" \
    --json "$out/isosurface.jsonl" > "$out/isosurface.txt" 2>&1 || echo "isosurface failed: $?"
fi
[[ $parts == *" skimage "* ]] && echo "== extraction against scikit-image" && python3 - "$bin" "$out" "${EXTRACT_SIZES:-256:uint8 512:float32}" <<'PY'
import json, re, subprocess, sys, time
import numpy as np
from skimage.measure import marching_cubes
bin, out = sys.argv[1], sys.argv[2]
rows = []
sizes = [(int(n), np.dtype(t).type) for n, t in (s.split(":") for s in sys.argv[3].split())]
for n, dtype in sizes:
    x, y, z = np.meshgrid(*(np.linspace(0, 12, n, dtype=np.float32),) * 3, indexing="ij")
    field = np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)
    field += 0.3 * np.sin(3.1 * x + 1.7 * y) * np.cos(2.3 * z)
    if dtype == np.uint8:
        field = np.round((field + 2) * 60).astype(np.uint8)
        level = 120.5
    else:
        level = 0.1037
    raw = f"/tmp/field{n}.raw"
    field.T.tofile(raw)  # x fastest
    t = time.perf_counter(); v, f, _, _ = marching_cubes(field.astype(np.float32), level); sk = time.perf_counter() - t
    name = np.dtype(dtype).name
    cmd = [bin, "extract", raw, "--dims", f"{n},{n},{n}", "--dtype", name, "--iso", str(level), "-o", f"/tmp/s{n}.ply"]
    text = subprocess.run(cmd, capture_output=True, text=True).stdout
    ms = float(re.search(r"extracted in ([0-9.]+) ms GPU", text).group(1))
    tris = int(re.search(r"iso [^:]+: (\d+) triangles", text).group(1))
    cpu_text = subprocess.run(cmd[:-2] + ["-o", f"/tmp/c{n}.ply", "--method", "cpu"],
                              capture_output=True, text=True).stdout
    cpu_ms = float(re.search(r"extracted in ([0-9.]+) ms", cpu_text).group(1))
    rows.append(dict(volume=f"{n}^3 {name}", triangles=tris, skimage_triangles=len(f),
                     gpu_extract_ms=ms, skimage_ms=sk * 1e3, speedup=sk * 1e3 / ms,
                     cpu_marching_cubes_ms=cpu_ms, line=text.strip()))
    print(f"{n}^3 {name}: {tris} tris, GPU meshlets {ms:.3f} ms, scikit-image {sk*1e3:.0f} ms "
          f"({len(f)} tris): {sk*1e3/ms:.0f}x; our CPU marching cubes {cpu_ms:.0f} ms: {cpu_ms/ms:.0f}x")
json.dump(rows, open(f"{out}/extract.json", "w"), indent=1)
PY
echo "== summary"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
for name in ("extraction", "iso-sweep", "isosurface"):
    try:
        lines = [json.loads(l) for l in open(f"{out}/{name}.jsonl")]
    except OSError:
        continue
    for r in lines:
        stages = " ".join(f'{s["stage"]}={s["median_ms"]:.3f}' for s in r["stages"])
        counts = r.get("counts", {})
        extra = " ".join(f"{k}={counts[k]:.0f}" for k in ("surface_bytes", "triangles_last_frame") if k in counts)
        extra += " " + " ".join(f"{k}={counts[k]:.3f}" for k in ("stored_bytes", "speedup_over_best_pmb", "bytes_over_smallest_pmb") if k in counts)
        print(f'{name:10} {r["dataset"]:28} {r["technique"]:10} {r.get("variant", ""):6} {r["path"]:8} {stages} {extra}')
PY
