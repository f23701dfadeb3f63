#!/usr/bin/env bash
# The batch bake on a real Slurm cluster: starts a one-node cluster on localhost (munged,
# slurmctld and slurmd from Debian's munge and slurm-wlm, every file in a temporary directory),
# submits the job-array script of docs/baking.md, taken from the document itself, as an array of
# 3 tasks over 4 meshes, waits for it, and checks that
#   - the shard summaries together name every input exactly once, each "ok";
#   - every asset holds the same geometry as the one a local batch (no shard) writes: the
#     meshes `ngi-eval mesh --lod 0 --no-sr` writes from the two are byte for byte equal (the
#     assets' bytes differ only in the bake report's stage timings).
# Usage: slurm_batch_test.sh NGI_BAKE_EXE NGI_EVAL_EXE DOCS_BAKING_MD
# Exit 0 pass, 1 fail, 77 skipped (Slurm not installed; never skipped when CI is set).
set -uo pipefail

bake_exe="$1"
eval_exe="$2"
doc="$3"
fail() { echo "FAIL: $*" >&2; exit 1; }

for tool in munged slurmctld slurmd sbatch sinfo; do
    if ! command -v "$tool" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$tool" ]; then
        [ -n "${CI:-}" ] && fail "$tool is not installed (tools/debian-packages.txt installs munge and slurm-wlm)"
        echo "SKIP: $tool is not installed (Debian packages munge and slurm-wlm)"
        exit 77
    fi
done
export PATH="$PATH:/usr/sbin"

work="$(mktemp -d /tmp/ngi-slurm.XXXXXX)"
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
    rm -rf "$work"
}
trap cleanup EXIT
cd "$work" || fail "cannot enter $work"
mkdir -p munge slurm/state slurm/spool data/meshes bin || fail "mkdir"

# The inputs: two spheres and two tori as OFF, written here (small and fast to bake).
sphere() {  # RINGS SEGMENTS
    awk -v R="$1" -v S="$2" 'BEGIN {
        pi = atan2(0, -1); nv = (R - 1) * S + 2; nf = 2 * S * (R - 1)
        print "OFF"; print nv, nf, 0
        print 0, 0, 1
        for (i = 1; i < R; ++i) for (j = 0; j < S; ++j) {
            t = pi * i / R; p = 2 * pi * j / S
            printf "%.7f %.7f %.7f\n", sin(t) * cos(p), sin(t) * sin(p), cos(t)
        }
        print 0, 0, -1
        for (j = 0; j < S; ++j) print 3, 0, 1 + j, 1 + (j + 1) % S
        for (i = 1; i < R - 1; ++i) for (j = 0; j < S; ++j) {
            a = 1 + (i - 1) * S + j; b = 1 + (i - 1) * S + (j + 1) % S
            c = 1 + i * S + j; d = 1 + i * S + (j + 1) % S
            print 3, a, c, d; print 3, a, d, b
        }
        last = nv - 1; base = 1 + (R - 2) * S
        for (j = 0; j < S; ++j) print 3, last, base + (j + 1) % S, base + j
    }'
}
torus() {  # MAJOR_SEGMENTS MINOR_SEGMENTS MINOR_RADIUS
    awk -v U="$1" -v V="$2" -v r="$3" 'BEGIN {
        pi = atan2(0, -1); print "OFF"; print U * V, 2 * U * V, 0
        for (i = 0; i < U; ++i) for (j = 0; j < V; ++j) {
            u = 2 * pi * i / U; v = 2 * pi * j / V
            printf "%.7f %.7f %.7f\n", (1 + r * cos(v)) * cos(u), (1 + r * cos(v)) * sin(u), r * sin(v)
        }
        for (i = 0; i < U; ++i) for (j = 0; j < V; ++j) {
            a = i * V + j; b = ((i + 1) % U) * V + j; c = ((i + 1) % U) * V + (j + 1) % V; d = i * V + (j + 1) % V
            print 3, a, b, c; print 3, a, c, d
        }
    }'
}
sphere 12 24 >data/meshes/sphere-a.off
sphere 16 20 >data/meshes/sphere-b.off
torus 32 16 0.45 >data/meshes/torus-a.off
torus 24 12 0.5 >data/meshes/torus-b.off

# ngi-bake on the PATH, with options that keep each bake to a few seconds (the job script is
# the document's, run as it stands in a directory laid out as it expects: data/meshes in,
# out/cgal out).
cat >bin/ngi-bake <<EOF
#!/bin/bash
exec "$bake_exe" "\$@" --resolution 64 --store-res 16 --remesh-vertices 800
EOF
chmod +x bin/ngi-bake
export PATH="$work/bin:$PATH"

# The job-array script, exactly as docs/baking.md shows it (the indented block that starts
# with #!/bin/bash after "On a Slurm cluster").
awk '/On a Slurm cluster/ { on = 1 } on && /^    #!\/bin\/bash/ { take = 1 }
     take && !/^    / { exit } take { sub(/^    /, ""); print }' "$doc" >bake.sh
grep -q 'SLURM_ARRAY_TASK_ID/\$SLURM_ARRAY_TASK_COUNT' bake.sh || fail "no job-array script found in $doc"
submit_line="$(grep -o 'sbatch --array=[^`]*bake.sh[^`]*' "$doc" | head -1)"
[ -n "$submit_line" ] || fail "no sbatch line found in $doc"
echo "job script from $doc:"; cat bake.sh; echo "submit line: $submit_line"

# munge: a fresh key, its own socket.
user="$(id -un)"
dd if=/dev/urandom of=munge/munge.key bs=1024 count=1 status=none
chmod 400 munge/munge.key
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
    --seed-file="$work/munge/munged.seed" || fail "munged did not start: $(cat munge/munged.log 2>/dev/null)"
pids+=("$(cat munge/munged.pid)")

# slurm.conf: one node (this machine as slurmd -C sees it), one partition, no cgroups.
node="$(slurmd -C | head -1)"
node_name="$(echo "$node" | sed -n 's/^NodeName=\([^ ]*\).*/\1/p')"
port=$((20000 + RANDOM % 20000))
cat >slurm/slurm.conf <<EOF
ClusterName=ngitest
SlurmctldHost=$node_name(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$work/slurm/state
SlurmdSpoolDir=$work/slurm/spool
SlurmctldPidFile=$work/slurm/slurmctld.pid
SlurmdPidFile=$work/slurm/slurmd.pid
SlurmctldLogFile=$work/slurm/slurmctld.log
SlurmdLogFile=$work/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SchedulerType=sched/backfill
$(echo "$node" | sed 's/^NodeName=[^ ]*/NodeName='"$node_name"' NodeAddr=127.0.0.1/') State=UNKNOWN
PartitionName=test Nodes=$node_name Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm/slurm.conf"
slurmctld -D -i >slurm/slurmctld.out 2>&1 &
pids+=($!)
slurmd -D -N "$node_name" >slurm/slurmd.out 2>&1 &
pids+=($!)
logs() { tail -n 20 slurm/slurmctld.log slurm/slurmd.log slurm/slurmctld.out slurm/slurmd.out 2>/dev/null; }
for _ in $(seq 60); do
    state="$(sinfo -h -N -o %t 2>/dev/null | head -1)"
    [ "$state" = idle ] && break
    sleep 1
done
[ "$state" = idle ] || { logs; fail "the Slurm node is not idle after 60 s (state '$state')"; }

# Submit the document's array (3 tasks over the 4 meshes) and wait for it.
submit="${submit_line/--array=0-15/--array=0-2}"
submit="${submit/bake.sh/--wait --output=$work/task-%a.log bake.sh}"
echo "running: $submit"
timeout 600 $submit || { logs; cat task-*.log 2>/dev/null; fail "the job array failed"; }
cat task-*.log

# Every input exactly once, each ok, in the merged shard summaries.
ls out/cgal/summary.shard-*-of-3.jsonl >/dev/null 2>&1 || fail "no shard summaries in out/cgal"
[ "$(ls out/cgal/summary.shard-*-of-3.jsonl | wc -l)" = 3 ] || fail "expected 3 shard summaries"
merged="$(cat out/cgal/summary*.jsonl)"
for m in sphere-a sphere-b torus-a torus-b; do
    n="$(echo "$merged" | grep -c "\"input\":\"[^\"]*meshes/$m.off\"")"
    [ "$n" = 1 ] || fail "$m.off is named $n times in the merged summaries"
    echo "$merged" | grep "meshes/$m.off" | grep -q '"status":"ok"' || fail "$m.off did not bake: $merged"
done
[ "$(echo "$merged" | wc -l)" = 4 ] || fail "the merged summaries have $(echo "$merged" | wc -l) lines, expected 4"

# The same assets as a local batch.
ngi-bake --batch data/meshes --out out/local >local.log 2>&1 || { cat local.log; fail "the local batch failed"; }
for m in sphere-a sphere-b torus-a torus-b; do
    for batch in cgal local; do
        "$eval_exe" mesh out/$batch/$m.ngi --lod 0 --no-sr -o out/$batch-$m.off >/dev/null || fail "ngi-eval mesh out/$batch/$m.ngi"
    done
    cmp out/cgal-$m.off out/local-$m.off || fail "$m.ngi holds other geometry in the Slurm batch than in the local one"
done
echo "PASS: 3 Slurm array tasks baked 4 meshes once each, with the geometry of a local batch"
