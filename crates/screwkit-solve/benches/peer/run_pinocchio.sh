#!/usr/bin/env bash
# Pinocchio's C++ next to screwkit's tree bench, interleaved in one run.
#
#   crates/screwkit-solve/benches/peer/run_pinocchio.sh [URDF [FRAME]] [--rounds N]
#
# Default: TALOS ($SCREWKIT_SHARED_URDF/trees/talos_full_v2.urdf, the CI data) and its left
# gripper's base link. Also the dynamics (rnea, computeGeneralizedGravity, crba, aba; fixed base;
# Pinocchio's C++ parser takes mimic joints as independent joints, so a file with mimic joints
# has more velocity entries there: compare on files without them).
# Prints, per round, screwkit's `SCREWKIT ...` line (benches/tree.rs) and Pinocchio's
# `PINOCCHIO ...` line (pinocchio_tree.cpp, the same protocol), then the minimum of each figure
# over the rounds and the ratios. Take the ratios, not the absolute figures (the host is shared).
#
# Pinocchio 4.1.0 from PyPI only (no internet but the registries): headers from the `pin`
# wheel and its cmeel dependencies (Eigen, Boost, urdfdom), installed in target/peer/venv, and the
# two URDF parser sources that the wheel ships compiled (src/parsers/urdf/{model,utils}.cpp) from
# the `pin` sdist, checked against PyPI's sha256. Everything is compiled into one binary with
# -O3 -DNDEBUG -march=native: the wheel's libpinocchio_*.so is baseline x86-64 code with 16-byte
# Eigen alignment, and mixing it with AVX-compiled Eigen code crashes (a Model freed with the wrong
# layout), so it is not linked at all; only urdfdom's and console_bridge's C++ libraries are (no
# Eigen in their interfaces). The build is cached in target/peer/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../../.." && pwd)"
peer="$repo/target/peer"
urdf="${SCREWKIT_SHARED_URDF:-}/trees/talos_full_v2.urdf"
frame="gripper_left_base_link"
rounds=3
pos=()
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds="$2"; shift 2 ;;
    *) pos+=("$1"); shift ;;
  esac
done
[ ${#pos[@]} -ge 1 ] && urdf="${pos[0]}"
[ ${#pos[@]} -ge 2 ] && frame="${pos[1]}"
[ -f "$urdf" ] || { echo "run_pinocchio.sh: no such URDF: $urdf (give one, or set SCREWKIT_SHARED_URDF for TALOS)" >&2; exit 2; }
# Absolute: the benches run in their crate's directory.
urdf="$(cd "$(dirname "$urdf")" && pwd)/$(basename "$urdf")"

version=4.1.0
mkdir -p "$peer"
if [ ! -x "$peer/venv/bin/python" ]; then
  python3 -m venv "$peer/venv"
fi
py="$peer/venv/bin/python"
if ! "$py" -c "import pinocchio" 2>/dev/null; then
  "$py" -m pip install --quiet "pin==$version" cmeel-eigen cmeel-urdfdom-headers
fi
prefix="$("$py" -c 'import cmeel, sys; print(sys.prefix)')/lib/python3.$("$py" -c 'import sys; print(sys.version_info[1])')/site-packages/cmeel.prefix"
[ -d "$prefix/include/pinocchio" ] || { echo "run_pinocchio.sh: no Pinocchio headers in $prefix" >&2; exit 1; }

src="$peer/pin-$version"
if [ ! -f "$src/src/parsers/urdf/model.cpp" ]; then
  "$py" - "$version" "$peer" <<'PY'
import hashlib, json, sys, tarfile, urllib.request
version, peer = sys.argv[1], sys.argv[2]
# PyPI's simple index (PEP 691 JSON): the registry this machine reaches.
req = urllib.request.Request(
    "https://pypi.org/simple/pin/", headers={"Accept": "application/vnd.pypi.simple.v1+json"}
)
files = json.load(urllib.request.urlopen(req))["files"]
sdist = next(f for f in files if f["filename"] == f"pin-{version}.tar.gz")
data = urllib.request.urlopen(sdist["url"]).read()
if hashlib.sha256(data).hexdigest() != sdist["hashes"]["sha256"]:
    raise SystemExit(f"{sdist['filename']}: sha256 differs from PyPI's")
path = f"{peer}/{sdist['filename']}"
open(path, "wb").write(data)
with tarfile.open(path) as t:
    members = [m for m in t.getmembers() if m.name.startswith(f"pin-{version}/src/parsers/urdf/")]
    t.extractall(peer, members=members, filter="data")
PY
fi

bin="$peer/pinocchio_tree"
if [ ! -x "$bin" ] || [ "$here/pinocchio_tree.cpp" -nt "$bin" ]; then
  echo "compiling Pinocchio $version (header-compiled, -O3 -march=native; about a minute) ..." >&2
  g++ -O3 -DNDEBUG -march=native -std=c++17 \
    -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
    -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
    -DPINOCCHIO_WITH_URDFDOM -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3 \
    -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0 -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0 \
    -I"$prefix/include" -I"$prefix/include/eigen3" -I"$prefix/include/urdfdom_headers" \
    -I"$prefix/include/urdfdom" \
    "$here/pinocchio_tree.cpp" "$src/src/parsers/urdf/model.cpp" "$src/src/parsers/urdf/utils.cpp" \
    -o "$bin.tmp" -L"$prefix/lib" -lurdfdom_model -lconsole_bridge -Wl,-rpath,"$prefix/lib" \
    2>"$peer/build.log" || { cat "$peer/build.log" >&2; exit 1; }
  mv "$bin.tmp" "$bin"
fi

cd "$repo"
cargo bench -p screwkit-solve --bench tree --no-run >/dev/null 2>&1
log="$peer/run.log"
: >"$log"
for _ in $(seq "$rounds"); do
  cargo bench -q -p screwkit-solve --bench tree -- "$urdf" "$frame" 2>/dev/null | tee -a "$log"
  "$bin" "$urdf" "$frame" | tee -a "$log"
done
"$py" - "$log" <<'PY'
import re, sys
best = {}
for line in open(sys.argv[1]):
    who = line.split()[0]
    if who not in ("SCREWKIT", "PINOCCHIO"):
        continue
    for key, val in re.findall(r"(\w+_ns)=([0-9.]+)", line):
        best[(who, key)] = min(best.get((who, key), float("inf")), float(val))
print("minimum over rounds (ns):")
for key in ("all_frames_fk_ns", "frame_jacobian_ns", "rnea_ns", "gravity_ns", "crba_ns", "aba_ns"):
    if ("SCREWKIT", key) not in best or ("PINOCCHIO", key) not in best:
        continue
    s, p = best[("SCREWKIT", key)], best[("PINOCCHIO", key)]
    print(f"  {key:18} screwkit {s:8.1f}  pinocchio {p:8.1f}  ratio {p / s:5.2f}x")
PY
