#!/usr/bin/env bash
# The converter under mpirun (tests/mpi/CMakeLists.txt): the same .vdb and
# mesh, byte for byte, from 1, 2 and 4 ranks (a synthetic torus, and the
# Stanford bunny when ../shared is beside the repository), also from depth
# frames, whose data term each rank holds in part (synthetic frames, and
# 7-Scenes' when ../shared is there), and frames along a street, of which each
# rank holds those its slab needs; pieces (--pieces)
# whose union is one process's level set, and whose mesh (levelfuse mesh of
# every piece) is one process's; a job too large for one process's
# memory budget runs on four ranks within it; a rank that fails (bad input, a
# memory limit it cannot meet, a piece it cannot write, killed mid-run) stops every rank,
# with a clear message, a non-zero exit and no output, and never hangs; so
# does Ctrl-C, also when it reaches one rank as the pieces are written.
#   cli_mpi_test.sh <levelfuse> <mpiexec> <scratch folder>
set -uo pipefail
levelfuse=$1
mpiexec=$2
work=$3
here=$(cd "$(dirname "$0")" && pwd)
export OMPI_MCA_btl_vader_single_copy_mechanism=none
run() { timeout 240 "$mpiexec" --oversubscribe --allow-run-as-root -np "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
"$levelfuse" synth --shape torus --noise 0.1 -o scans >/dev/null || fail "synth"

# 1. One process, then 2 and 4 ranks: identical outputs.
"$levelfuse" reconstruct scans/scans.json -o one.vdb --mesh one.ply -q || fail "one process"
for ranks in 2 4; do
  run "$ranks" "$levelfuse" reconstruct scans/scans.json -o "r$ranks.vdb" --mesh "r$ranks.ply" --json > "r$ranks.json" ||
    fail "$ranks ranks exited with $?"
  cmp one.vdb "r$ranks.vdb" || fail "$ranks ranks: the .vdb differs from one process's"
  cmp one.ply "r$ranks.ply" || fail "$ranks ranks: the mesh differs from one process's"
  # The summary, printed once, says what each rank's share cost.
  python3 - "r$ranks.json" "$ranks" <<'PY' || fail "$ranks ranks: the summary's ranks: $(cat "r$ranks.json")"
import json, sys
summary = json.load(open(sys.argv[1]))
ranks = summary["ranks"]
assert len(ranks) == int(sys.argv[2])
assert all(r["leaf_nodes"] > 0 and r["peak_memory_bytes"] > 0 and r["seconds"] > 0 and r["ghost_bytes_sent"] > 0
           for r in ranks)
PY
done

# The Stanford bunny's ten scans at its own resolution (0.5 mm), when the shared data are beside the repository.
bunny="$here/../../../shared/data/stanford/bunny/bun.conf"
if [ -f "$bunny" ]; then
  "$levelfuse" reconstruct "$bunny" -o bunny1.vdb --json > bunny1.json || fail "bunny, one process"
  for ranks in 2 4; do
    run "$ranks" "$levelfuse" reconstruct "$bunny" -o "bunny$ranks.vdb" --json > "bunny$ranks.json" ||
      fail "bunny, $ranks ranks"
    cmp bunny1.vdb "bunny$ranks.vdb" || fail "bunny, $ranks ranks: the .vdb differs from one process's"
    # Rank 0 measures the fit to the points the scanner measured; the other ranks let those points go.
    python3 - bunny1.json "bunny$ranks.json" <<'PY' || fail "bunny, $ranks ranks: the fit differs from one process's"
import json, sys
one, team = (json.load(open(name)) for name in sys.argv[1:])
assert one["fit"] is not None and one["points"] > 300000, one
assert team["fit"] == one["fit"] and team["points"] == one["points"], (team["fit"], one["fit"])
PY
  done
else
  echo "the bunny's scans are not at $bunny: its part of the test is left out"
fi

# 1a. Depth frames (one grid, the data term from grids): each rank integrates its slab of the data
#     alone and makes its slab of the initial model from it; the outputs are one process's, byte for
#     byte. Forty synthetic frames of the torus, and 7-Scenes' fifty when the shared data are beside
#     the repository.
"$levelfuse" synth --shape torus --pinhole --views 40 --resolution 100 --noise 0.1 -o frames >/dev/null ||
  fail "synth frames"
frameRuns=("frames/scans.json")
sevenScenes="$here/../../../shared/data/7scenes"
[ -d "$sevenScenes" ] && frameRuns+=("$sevenScenes --voxel-size 0.02")
for k in "${!frameRuns[@]}"; do
  # shellcheck disable=SC2086 # the run's input and options, split on purpose
  "$levelfuse" reconstruct ${frameRuns[$k]} -o "frames$k-1.vdb" --mesh "frames$k-1.ply" --json > "frames$k-1.json" ||
    fail "frames ${frameRuns[$k]}, one process"
  for ranks in 2 4; do
    # shellcheck disable=SC2086
    run "$ranks" "$levelfuse" reconstruct ${frameRuns[$k]} -o "frames$k-$ranks.vdb" --mesh "frames$k-$ranks.ply" \
      --json > "frames$k-$ranks.json" || fail "frames ${frameRuns[$k]}, $ranks ranks exited with $?"
    cmp "frames$k-1.vdb" "frames$k-$ranks.vdb" || fail "frames ${frameRuns[$k]}, $ranks ranks: the .vdb differs"
    cmp "frames$k-1.ply" "frames$k-$ranks.ply" || fail "frames ${frameRuns[$k]}, $ranks ranks: the mesh differs"
  done
done
# More ranks than the frames' data have columns of leaf nodes: every rank says so, and nothing is written.
run 4 "$levelfuse" reconstruct frames/scans.json --voxel-size 0.5 -o coarse.vdb -q 2> coarse.err &&
  fail "4 ranks sharing 2 columns of data exited 0"
grep -q "spans 2 columns of leaf nodes, too few for 4 slabs: use fewer processes" coarse.err ||
  fail "4 ranks sharing 2 columns of data: $(cat coarse.err)"
[ ! -e coarse.vdb ] || fail "4 ranks sharing 2 columns of data wrote coarse.vdb"

# Each rank holds its slab's part of the data term, and 24 voxels beyond each cut: in 7-Scenes'
# room at 2 cm (25 columns of leaf nodes across, the margins 3 columns a side) the ranks of 2
# held 0.85 and 0.76 of one process's data term, those of 4 from 0.26 to 0.78 (a mean of 0.53).
if [ -d "$sevenScenes" ]; then
  python3 - frames1-1.json frames1-2.json frames1-4.json <<'PY' || fail "7-Scenes: the ranks' data terms"
import json, sys
whole = json.load(open(sys.argv[1]))["data_term_bytes"]
assert whole > 0, "one process reports no data term"
for name, ranks, mean in ((sys.argv[2], 2, 0.9), (sys.argv[3], 4, 0.65)):
    held = [r["data_term_bytes"] for r in json.load(open(name))["ranks"]]
    assert len(held) == ranks and all(0 < b < whole for b in held), (name, whole, held)
    assert sum(held) / ranks < mean * whole, (name, whole, held)
PY
fi

# `name`: the scans `input` reconstructed at 2 cm by one process, then by 2 and 4 ranks, give the
# same .vdb and mesh; each run's summary is name-<ranks>.json.
sameOnRanks() {
  local name=$1 input=$2
  "$levelfuse" reconstruct "$input" --voxel-size 0.02 -o "$name-1.vdb" --mesh "$name-1.ply" --json > "$name-1.json" ||
    fail "$name, one process"
  for ranks in 2 4; do
    run "$ranks" "$levelfuse" reconstruct "$input" --voxel-size 0.02 -o "$name-$ranks.vdb" --mesh "$name-$ranks.ply" \
      --json > "$name-$ranks.json" || fail "$name, $ranks ranks exited with $?"
    cmp "$name-1.vdb" "$name-$ranks.vdb" || fail "$name, $ranks ranks: the .vdb differs"
    cmp "$name-1.ply" "$name-$ranks.ply" || fail "$name, $ranks ranks: the mesh differs"
  done
}

# 1b'. Coarse to fine from grids (40 views of the torus, more than the 32 that take the data term
#     from the maps): each rank integrates each grid but the coarsest within its slab of that grid
#     once it is cut; the outputs are one process's, and no rank holds the whole data term.
"$levelfuse" synth --shape torus --views 40 --resolution 80 --noise 0.1 -o many >/dev/null || fail "synth many"
sameOnRanks many many/scans.json
python3 - many-1.json many-4.json <<'PY' || fail "many views: the ranks' data terms"
import json, sys
one, four = (json.load(open(name)) for name in sys.argv[1:])
assert one["levels"] > 1 and one["data_term_bytes"] > 0, one
# Measured: 0.68, 0.90, 0.87 and 0.66 of one process's (the margins are wide beside this torus).
held = [r["data_term_bytes"] for r in four["ranks"]]
assert all(0 < b < 0.95 * one["data_term_bytes"] for b in held), (one["data_term_bytes"], held)
assert sum(held) / 4 < 0.85 * one["data_term_bytes"], (one["data_term_bytes"], held)
PY

# 1c. Frames along a street (levelfuse synth --shape street), each seeing about 2 m of it: the
#     ranks read the frames in turn, then each holds those its slab needs (their windows reach
#     its slab of the data, or their lines of sight the blocks carving decides there). The
#     outputs are one process's; rank 0, which measures and writes the whole surface, holds
#     every frame; with --pieces no rank holds them all (measured with 4 ranks: 24, 30, 30
#     and 24 of the 80), and the pieces are those of the run without --pieces.
"$levelfuse" synth --shape street --views 80 --resolution 96 --noise 0.003 -o street >/dev/null || fail "synth street"
sameOnRanks street street/scans.json
run 4 "$levelfuse" reconstruct street/scans.json --voxel-size 0.02 -o street-pieces.vdb --pieces --json \
  > street-pieces.json || fail "street in pieces exited with $?"
python3 - street-4.json street-pieces.json <<'PY' || fail "street: the frames each rank held"
import json, sys
whole, pieces = ([r["scans_held"] for r in json.load(open(name))["ranks"]] for name in sys.argv[1:])
assert whole[0] == 80 and all(0 < n < 48 for n in whole[1:]), whole
assert all(0 < n < 48 for n in pieces) and sum(pieces) < 2 * 80, pieces
PY

# 1b. Pieces (--pieces): each of 3 ranks writes its own piece of the level set; together they
#     are one process's level set (their CSG union), and each says which piece it is.
run 3 "$levelfuse" reconstruct scans/scans.json -o pieces.vdb --pieces --json > pieces.json || fail "pieces: exit $?"
/usr/bin/python3 - <<'PY' || fail "pieces: $(cat pieces.json)"
import json
import pyopenvdb as vdb
summary = json.load(open("pieces.json"))
names = ["pieces.%d-of-3.vdb" % r for r in range(3)]
assert summary["outputs"]["vdb"] == names and summary["fit"] is None, summary["outputs"]
whole = [g for g in vdb.readAll("one.vdb")[0] if g.name == "surface"][0]
pieces = [{g.name: g for g in vdb.readAll(name)[0]} for name in names]
united = pieces[0]["surface"].deepCopy()
for r, piece in enumerate(pieces):
    assert piece["surface"].metadata["levelfuse_piece"] == r and piece["surface"].metadata["levelfuse_pieces"] == 3
    assert piece["weight"].activeVoxelCount() == piece["surface"].activeVoxelCount()
    if r > 0:
        assert piece["surface"].metadata["levelfuse_piece_begin_x"] == pieces[r - 1]["surface"].metadata["levelfuse_piece_end_x"]
        united.combine(piece["surface"].deepCopy(), lambda a, b: min(a, b))
assert united.activeVoxelCount() == whole.activeVoxelCount() == summary["narrow_band_voxels"]
values = united.getConstAccessor()
assert all(values.getValue(v.min) == v.value for v in whole.citerOnValues()), "a value differs"
PY
# The pieces put together by levelfuse mesh: the mesh of one process's level set, byte for byte;
# anything but every piece once is refused, naming the file, and nothing is written.
"$levelfuse" mesh pieces.0-of-3.vdb pieces.1-of-3.vdb pieces.2-of-3.vdb -o pieces-mesh.ply > /dev/null ||
  fail "pieces: levelfuse mesh of the pieces exited with $?"
"$levelfuse" mesh one.vdb -o one-mesh.ply > /dev/null || fail "pieces: levelfuse mesh of one.vdb exited with $?"
cmp one-mesh.ply pieces-mesh.ply || fail "pieces: the mesh of the pieces differs from that of one process's level set"
for given in "pieces.0-of-3.vdb pieces.2-of-3.vdb|pieces.0-of-3.vdb: piece 1 of 3, but 2 files were given" \
             "pieces.1-of-3.vdb pieces.1-of-3.vdb pieces.2-of-3.vdb|pieces.1-of-3.vdb: piece 2 of 3 was given twice" \
             "pieces.0-of-3.vdb one.vdb pieces.2-of-3.vdb|one.vdb: 'surface' is a whole level set, not a piece"; do
  # shellcheck disable=SC2086
  "$levelfuse" mesh ${given%%|*} -o refused.ply 2> refused.err && fail "pieces: levelfuse mesh took ${given%%|*}"
  grep -q "${given#*|}" refused.err || fail "pieces: levelfuse mesh ${given%%|*}: $(cat refused.err)"
  [ ! -e refused.ply ] || fail "pieces: levelfuse mesh ${given%%|*} wrote a mesh"
done

# A rank that cannot write its piece (a file size limit): no rank's piece is written, nor left half-made.
cat > smallfiles.sh <<SCRIPT
#!/usr/bin/env bash
[ "\${OMPI_COMM_WORLD_RANK:-0}" = 2 ] && trap '' XFSZ && ulimit -f 16
exec "$levelfuse" "\$@"
SCRIPT
chmod +x smallfiles.sh
mkdir unwritten
# Over loopback TCP: OpenMPI's shared memory would meet the file size limit at the start.
OMPI_MCA_btl=self,tcp run 3 ./smallfiles.sh reconstruct scans/scans.json -o unwritten/pieces.vdb --pieces -q \
  2> unwritten.err
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "unwritable piece: exit code $code"
# Whichever rank's line comes first, it says why rank 2 failed.
grep -q "cannot write 'unwritten/pieces.2-of-3.vdb'" unwritten.err ||
  fail "unwritable piece: no message saying why: $(cat unwritten.err)"
[ -z "$(ls -A unwritten)" ] || fail "unwritable piece: files were left: $(ls -A unwritten)"

# 2. Bad input: every rank fails alike; the job ends with the one-line error naming the file.
echo '{"scans": [{"format": "nope"}]}' > bad.json
run 2 "$levelfuse" reconstruct bad.json -o bad.vdb 2> bad.err
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "bad input: exit code $code"
grep -q "bad.json: scans\[0\]: unknown format 'nope'" bad.err || fail "bad input: no message naming the file"
[ ! -e bad.vdb ] || fail "bad input: an output was written"
# A frame that only one rank reads first (the ranks read the frames in turn): that rank ends the job.
cp -r street brokenstreet && head -c 100 street/scan3.pfm > brokenstreet/scan3.pfm
run 2 "$levelfuse" reconstruct brokenstreet/scans.json --voxel-size 0.02 -o broken.vdb 2> broken.err
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "a frame one rank reads: exit code $code"
grep -q "scan3.pfm.*(rank 1 of 2)" broken.err || fail "a frame one rank reads: $(cat broken.err)"
[ ! -e broken.vdb ] || fail "a frame one rank reads: an output was written"

# 3. One rank of two cannot have the memory its grids need: it says so, and the job stops.
cat > limited.sh <<SCRIPT
#!/usr/bin/env bash
[ "\${OMPI_COMM_WORLD_RANK:-0}" = 1 ] && ulimit -v 1500000
exec "$levelfuse" "\$@"
SCRIPT
chmod +x limited.sh
run 2 ./limited.sh reconstruct scans/scans.json --voxel-size 0.0015 -o limited.vdb 2> limited.err
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "memory limit: exit code $code"
grep -q "rank 1 of 2" limited.err || fail "memory limit: no message from the rank that failed: $(cat limited.err)"
[ ! -e limited.vdb ] || fail "memory limit: an output was written"

# 4. A job too large for one process's memory budget (--max-memory) runs on four ranks, each
#    within it: every rank asks only for its share of the finest grid.
"$levelfuse" reconstruct scans/scans.json --voxel-size 0.01 --max-memory 0.06 -o budget1.vdb -q 2> budget1.err &&
  fail "memory budget: one process took a job larger than its budget"
grep -q "needs about .* more than the 61.4 MiB levelfuse may use" budget1.err ||
  fail "memory budget: one process's refusal: $(cat budget1.err)"
run 4 "$levelfuse" reconstruct scans/scans.json --voxel-size 0.01 --max-memory 0.06 -o budget4.vdb -q ||
  fail "memory budget: four ranks, each within the budget, exited with $?"
[ -s budget4.vdb ] || fail "memory budget: four ranks wrote no .vdb"

# 5. One rank of four killed mid-run: every rank stops, nothing is written.
run 4 "$levelfuse" reconstruct scans/scans.json --voxel-size 0.004 -o "$work/killed.vdb" -q 2> killed.err &
job=$!
trap 'pkill -9 -f -- "$work/killed.vdb"' EXIT
ranks() {
  for p in $(pgrep -f -- "$work/killed.vdb"); do
    [ "$(cat "/proc/$p/comm" 2>/dev/null)" = levelfuse ] && echo "$p"
  done
}
victim=""
for _ in $(seq 100); do
  sleep 0.2
  [ "$(ranks | wc -l)" -eq 4 ] && victim=$(ranks | sed -n 3p) && break
done
[ -n "$victim" ] || fail "killed rank: the ranks did not start"
sleep 1
kill -9 "$victim"
wait "$job"
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "killed rank: exit code $code"
[ -z "$(ranks)" ] || fail "killed rank: ranks still run"
[ ! -e killed.vdb ] || fail "killed rank: an output was written"

# 6. Ctrl-C: mpirun passes SIGINT to every rank, and each says it was interrupted, writing nothing.
run 4 "$levelfuse" reconstruct scans/scans.json --voxel-size 0.004 -o "$work/interrupted.vdb" -q 2> interrupted.err &
job=$!
started=""
for _ in $(seq 100); do
  sleep 0.2
  [ "$(pgrep -f -- "$work/interrupted.vdb" | wc -l)" -ge 4 ] && started=yes && break
done
[ -n "$started" ] || fail "Ctrl-C: the ranks did not start"
sleep 1
for p in $(pgrep -f -- "$work/interrupted.vdb"); do  # mpirun itself, as a terminal's Ctrl-C reaches it
  case "$(cat "/proc/$p/comm" 2>/dev/null)" in mpiexec | mpirun | orterun) kill -INT "$p" ;; esac
done
wait "$job"
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "Ctrl-C: exit code $code"
grep -q "interrupted while .* of 4); nothing written" interrupted.err || fail "Ctrl-C: $(cat interrupted.err)"
[ ! -e interrupted.vdb ] || fail "Ctrl-C: an output was written"

# 6b. Ctrl-C reaching one rank of three as it writes its piece (--pieces): the others
#     have written theirs, and every piece is let go.
cat > interruptwriting.sh <<SCRIPT
#!/usr/bin/env bash
[ "\${OMPI_COMM_WORLD_RANK:-0}" = 1 ] && export LEVELFUSE_TEST_SIGNAL_AT=writing
exec "$levelfuse" "\$@"
SCRIPT
chmod +x interruptwriting.sh
mkdir interruptedpieces
run 3 ./interruptwriting.sh reconstruct scans/scans.json -o interruptedpieces/pieces.vdb --pieces -q \
  2> interruptedpieces.err
code=$?
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || fail "Ctrl-C while writing pieces: exit code $code"
grep -q "interrupted while writing (rank 1 of 3); nothing written" interruptedpieces.err ||
  fail "Ctrl-C while writing pieces: $(cat interruptedpieces.err)"
grep -q "rank 1 of 3 could not write its piece (interrupted); no piece written" interruptedpieces.err ||
  fail "Ctrl-C while writing pieces: the other ranks did not say why: $(cat interruptedpieces.err)"
[ -z "$(ls -A interruptedpieces)" ] || fail "Ctrl-C while writing pieces: files were left: $(ls -A interruptedpieces)"
echo "ok"
