#!/usr/bin/env bash
# Option validation of `uvmesh mesh` and `uvmesh2d`: non-positive, NaN or infinite sizes,
# hmin > hmax, unknown output formats, unwritable output and report paths. Each must give
# exit 1 (uvmesh) or 2 (uvmesh2d: its usage status), exactly one line on stderr that
# names the offending option or path, and no output file. The checks run before the
# model is read, except hmin against a relative or default hmax and the face ids of
# --face-size, which need the model.
#
# usage: bad_options.sh UVMESH UVMESH2D MODEL.step POLY
set -uo pipefail
uvmesh=$1 uvmesh2d=$2 model=$3 poly=$4
limit=${ROBUST_TIMEOUT:-10}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/uvmesh_opts.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
failures=0 checked=0
mkdir -p "$tmp/o"
# An unwritable place that stays unwritable for root (the CI user may be root): a path
# under a regular file.
: >"$tmp/file"

# expect_error STATUS NEEDLE CMD...: exit STATUS, one stderr line containing NEEDLE,
# nothing written in $tmp/o.
expect_error() {
  local status=$1 needle=$2
  shift 2
  checked=$((checked + 1))
  timeout -k 5 "$limit" "$@" >/dev/null 2>"$tmp/err"
  local rc=$? lines
  lines=$(wc -l <"$tmp/err")
  if [ $rc -ne "$status" ]; then
    echo "FAIL: exit $rc, expected $status: $*"
    sed 's/^/    /' "$tmp/err" | head -5
    failures=$((failures + 1))
  elif [ "$lines" -ne 1 ] || ! grep -qF -- "$needle" "$tmp/err"; then
    echo "FAIL: expected one stderr line containing '$needle', got $lines: $*"
    sed 's/^/    /' "$tmp/err" | head -5
    failures=$((failures + 1))
  fi
  if [ -n "$(ls -A "$tmp/o")" ]; then
    echo "FAIL: files left behind: $*: $(ls -A "$tmp/o")"
    failures=$((failures + 1))
    rm -rf "${tmp:?}/o"/*
  fi
}

out=$tmp/o/out.msh
m() { expect_error "$1" "$2" "$uvmesh" mesh "$model" "${@:3}"; }

for opt in --hmax --hmin --hmax-rel --chordal; do
  for v in -1 0 nan inf -inf 1e999 abc; do
    m 1 "$opt" -o "$out" "$opt" "$v"
  done
done
m 1 "--hmin 5 is larger than hmax 1" -o "$out" --hmin 5 --hmax 1
m 1 "is larger than hmax" -o "$out" --hmin 5 --hmax-rel 0.001
m 1 "is larger than hmax" -o "$out" --hmin 1e6
m 1 "--grad" -o "$out" --grad 0.5
m 1 "--angle" -o "$out" --angle -3
m 1 "--threads" -o "$out" --threads -2
m 1 "out.xyz: unknown mesh extension" -o "$tmp/o/out.xyz"
m 1 "out: unknown mesh extension" -o "$tmp/o/out"
m 1 "unknown format 'foo'" -o "$out" --format foo
m 1 "/nonexistent_dir/out.msh: cannot create a file there" -o /nonexistent_dir/out.msh
m 1 "file/out.msh: cannot create a file there" -o "$tmp/file/out.msh"
m 1 "file/r.json: cannot create a file there" -o "$out" --report "$tmp/file/r.json"
m 1 "given both as the mesh and as the report" -o "$out" --report "$out"
m 1 "expected ID=SIZE" -o "$out" --face-size 3=-1
m 1 "--face-size names face 100000" -o "$out" --face-size 100000=1
# A missing argument: CLI11's message, still one line and exit 1.
expect_error 1 "MODEL" "$uvmesh" mesh -o "$out"

mkdir -p "$tmp/dir.msh"
m 1 "dir.msh: is a directory" -o "$tmp/dir.msh"

p() { expect_error 2 "$1" "$uvmesh2d" "$poly" "${@:2}"; }
for v in -1 0 nan inf; do p "--size" -o "$tmp/o/out.mesh" --size "$v"; done
p "unknown extension" -o "$tmp/o/out.xyz"
p "file/out.mesh" -o "$tmp/file/out.mesh"
p "nonexistent_dir" -o /nonexistent_dir/out.mesh

echo "bad_options: $checked runs, $failures failure(s)"
[ "$failures" -eq 0 ]
