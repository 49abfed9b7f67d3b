#!/usr/bin/env bash
# Bad input, end to end: every file in ../shared/data/bad through `uvmesh info` and
# `uvmesh mesh`, the malformed OBJ cages and .poly files in data/ through `uvmesh mesh`
# and `uvmesh2d`. A rejected file must give
#   - a non-zero exit status, not a signal and not the time limit (a hang check: 10 s by
#     default, ROBUST_TIMEOUT for slow sanitizer builds),
#   - exactly one line on stderr, naming the file,
#   - no output file (not even a temporary beside it).
# The corpus' files that are valid or repairable (MANIFEST "expect: loads") must load
# within the time limit and mesh within 6 times it instead (occt_bearing_axis is 18 solids
# fused into 180 k triangles, ~5 s of CPU: at 10 s it failed on a loaded 2-core machine);
# a face that cannot be meshed is reported by id and exits 3, with the rest of the mesh
# written (docs/ARCHITECTURE.md, Contracts).
#
# usage: bad_inputs.sh UVMESH UVMESH2D BAD_DIR
set -uo pipefail
uvmesh=$1 uvmesh2d=$2 bad=$3
here=$(cd "$(dirname "$0")" && pwd)
limit=${ROBUST_TIMEOUT:-10}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/uvmesh_robust.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
failures=0 checked=0

fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# run NAME CMD...: runs CMD under the time limit, stderr to $tmp/err, sets $rc.
run() {
  local name=$1
  shift
  timeout -k 5 "$limit" "$@" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  checked=$((checked + 1))
  if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
    fail "$name: no answer within ${limit} s (hang): $*"
    return 1
  fi
  if [ $rc -ge 128 ]; then
    fail "$name: killed by signal $((rc - 128)): $*"
    sed 's/^/    /' "$tmp/err" | head -20
    return 1
  fi
  return 0
}

# expect_rejected NAME FILE OUTDIR CMD...: non-zero exit, one stderr line naming FILE,
# nothing left in OUTDIR.
expect_rejected() {
  local name=$1 file=$2 outdir=$3
  shift 3
  if ! run "$name" "$@"; then
    rm -rf "${outdir:?}"/*
    return
  fi
  local lines
  lines=$(wc -l <"$tmp/err")
  if [ "$rc" -eq 0 ]; then
    fail "$name: exit 0 for a bad input: $*"
  elif [ "$lines" -ne 1 ]; then
    fail "$name: expected one line on stderr, got $lines: $*"
    sed 's/^/    /' "$tmp/err" | head -10
  elif ! grep -qF -- "$(basename "$file")" "$tmp/err"; then
    fail "$name: the message does not name $(basename "$file"): $(cat "$tmp/err")"
  fi
  if [ -n "$(ls -A "$outdir")" ]; then
    fail "$name: left files behind: $(ls -A "$outdir")"
  fi
  rm -rf "${outdir:?}"/*
}

# Corpus files expected to load (MANIFEST.tsv: "expect: loads ..."): valid or repairable
# models, kept in bad/ because other tools crash or misread them.
loads=" occt_bad_header.igs occt_bearing_axis.brep occt_corrupted.stp "

mkdir -p "$tmp/o"
n_bad=0
for f in "$bad"/*; do
  [ -f "$f" ] || continue
  n_bad=$((n_bad + 1))
  b=$(basename "$f")
  if [[ $loads == *" $b "* ]]; then
    run "info $b" "$uvmesh" info "$f" && [ "$rc" -ne 0 ] && fail "info $b: exit $rc, expected the model to load: $(cat "$tmp/err")"
    # A failed run (hang, signal) is reported by run; its output is cleared all the same,
    # or the next file would be blamed for it.
    reject_limit=$limit
    limit=$((reject_limit * 6))
    run "mesh $b" "$uvmesh" mesh "$f" -o "$tmp/o/out.msh" -q --threads 2
    ran=$?
    limit=$reject_limit
    if [ "$ran" -ne 0 ]; then
      rm -rf "${tmp:?}/o"/*
      continue
    fi
    if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
      fail "mesh $b: exit $rc, expected 0 or 3 (faces failed): $(cat "$tmp/err")"
    elif [ "$rc" -eq 3 ] && ! grep -q "^uvmesh: face [0-9]* not meshed: " "$tmp/err"; then
      fail "mesh $b: exit 3 without naming the failed faces"
    elif [ ! -s "$tmp/o/out.msh" ]; then
      fail "mesh $b: exit $rc but no mesh written"
    fi
    rm -rf "$tmp/o"/*
    continue
  fi
  expect_rejected "info $b" "$f" "$tmp/o" "$uvmesh" info "$f"
  expect_rejected "mesh $b" "$f" "$tmp/o" "$uvmesh" mesh "$f" -o "$tmp/o/out.msh" --threads 2
done
[ "$n_bad" -ge 11 ] || fail "expected the 11 corpus files in $bad, found $n_bad"

# Malformed subdivision cages and .poly domains (ours, in data/).
# An empty cage is made here (an empty file in the repository would look like a copy of
# the corpus' own empty files).
: > "$tmp/obj_empty.obj"
for f in "$here"/data/obj_*.obj "$tmp/obj_empty.obj"; do
  expect_rejected "mesh $(basename "$f")" "$f" "$tmp/o" "$uvmesh" mesh "$f" -o "$tmp/o/out.msh" --threads 2
done
for f in "$here"/data/poly_*.poly; do
  expect_rejected "uvmesh2d $(basename "$f")" "$f" "$tmp/o" "$uvmesh2d" "$f" -o "$tmp/o/out.mesh"
done

echo "bad_inputs: $checked runs, $failures failure(s)"
[ "$failures" -eq 0 ]
