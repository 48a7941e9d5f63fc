#!/usr/bin/env bash
# Stability of the acceptance tier over base seeds (issue 29 item 5): run one
# figure at `--tier acceptance` for base seeds FIRST..LAST, one seed at a
# time, and file each finished seed's summary.json under
# docs/acceptance/FIGURE/seed-N/FIGURE/, its timing in times.log and the
# refreshed verdict table in stability.md.
#
#   docs/acceptance/run-seeds.sh FIGURE FIRST LAST [--threads N] [--work DIR] [--commit] [--refile] [--as NAME -- ARGS...]
#
# - A seed already filed is skipped; an interrupted seed resumes from the runs
#   saved in DIR/seed-N (default DIR: target/acceptance/FIGURE).
# - --refile runs filed seeds again and replaces their summaries (after a
#   change of the analysis: where DIR/seed-N holds the runs, only the analysis
#   reruns); times.log marks the line "refiled".
# - Several machines share the work by taking disjoint seed ranges; copy their
#   docs/acceptance/FIGURE/seed-N folders together and rerun
#   `target/release/acceptance stability` (the last lines of this script).
# - --commit commits the filed items (and a cut's cut.txt) after every seed, so that a
#   machine that goes away loses at most the seed under way.
# - --as NAME -- ARGS...: a cut of the figure. ARGS are passed to the binary
#   after the tier, seed, threads and output (e.g. `--sizes 220x11
#   --no-spectra`), and the seeds are filed under docs/acceptance/NAME/
#   instead (default DIR: target/acceptance/NAME), so a cut never mixes with
#   the whole figure's seed sets. NAME/cut.txt records "FIGURE ARGS"; `report
#   --seed-sets` grades the cut's checks over its seed sets where the whole
#   figure has too few. A cut computes fewer checks at the same
#   set-up and seeds; show, for one seed, that its checks equal the whole
#   figure's.
# - Needs `cargo build --release --bins` first. Each figure picks its own
#   engine at this tier (fast for the pipe, the reference for the hopper).
set -euo pipefail
usage() {
    echo "usage: $0 FIGURE FIRST LAST [--threads N] [--work DIR] [--commit] [--refile] [--as NAME -- ARGS...]" >&2
    exit 2
}
[ $# -ge 3 ] || usage
fig=$1 first=$2 last=$3
shift 3
threads=2 work="" commit=0 refile=0 name="" extra=()
while [ $# -gt 0 ]; do
    case $1 in
        --threads) [ $# -ge 2 ] || usage; threads=$2; shift 2 ;;
        --work) [ $# -ge 2 ] || usage; work=$2; shift 2 ;;
        --commit) commit=1; shift ;;
        --refile) refile=1; shift ;;
        --as) [ $# -ge 2 ] || usage; name=$2; shift 2 ;;
        --) shift; extra=("$@"); break ;;
        *) usage ;;
    esac
done
# a cut has a name of its own and something to cut; the one needs the other
[ -z "$name" ] && [ ${#extra[@]} -gt 0 ] && { echo "ARGS after -- need --as NAME (a cut is filed under its own name)" >&2; exit 2; }
[ -n "$name" ] && [ ${#extra[@]} -eq 0 ] && { echo "--as $name needs ARGS after -- (the options that cut the figure)" >&2; exit 2; }
[[ -z "$name" || $name =~ ^[a-z0-9-]+$ ]] || { echo "--as NAME must be lower-case letters, digits and '-', got '$name'" >&2; exit 2; }
[[ $first =~ ^[0-9]+$ && $last =~ ^[0-9]+$ && $first -le $last ]] || {
    echo "FIRST and LAST must be whole numbers with FIRST <= LAST, got '$first' and '$last'" >&2
    exit 2
}
cd "$(dirname "$0")/../.."
bin=target/release/$fig
[ -x "$bin" ] || { echo "no $bin: run 'cargo build --release --bins' first (FIGURE is a figure binary, e.g. waves-fig9)" >&2; exit 2; }
[ -x target/release/acceptance ] || { echo "no target/release/acceptance: run 'cargo build --release --bins' first" >&2; exit 2; }
if [ -n "$name" ]; then
    # a cut never writes into a whole figure's folder (or any other that is
    # not a cut's): the report would read it as both
    [ "$name" != "$fig" ] || { echo "--as $name: a cut needs a name other than its figure's" >&2; exit 2; }
    [ ! -d "docs/acceptance/$name" ] || [ -f "docs/acceptance/$name/cut.txt" ] || {
        echo "--as $name: docs/acceptance/$name exists and holds no cut.txt, so it is not a cut's folder; choose another name" >&2
        exit 2
    }
fi
label=${name:-$fig}
work=${work:-target/acceptance/$label}
docs=docs/acceptance/$label
mkdir -p "$docs" "$work"
if [ -n "$name" ]; then
    # the cut's figure and options, which `report --seed-sets` reads; one
    # folder holds one cut
    cut="$fig ${extra[*]}"
    if [ -f "$docs/cut.txt" ] && [ "$(cat "$docs/cut.txt")" != "$cut" ]; then
        echo "$docs/cut.txt is '$(cat "$docs/cut.txt")', not '$cut': a folder holds one cut; choose another --as" >&2
        exit 2
    fi
    echo "$cut" > "$docs/cut.txt"
fi
# the seed sets hold the fixed design: the figures that grade sequentially
# by default run their fixed count (drivers::acceptance: 128 runs, per
# point for the sweeps), so every seed set grades the same runs
case $fig in
    fig2|waves-fig6|waves-fig8|waves-fig9|waves-fig10) extra=(--fixed-runs 128 "${extra[@]}") ;;
esac
TIMEFORMAT='%R %U %S'
for s in $(seq "$first" "$last"); do
    filed=$docs/seed-$s/$fig/summary.json
    again=""
    if [ -f "$filed" ]; then
        [ $refile = 1 ] || { echo "seed $s: filed already, skipped"; continue; }
        again=" refiled"
    fi
    echo "seed $s: $bin --tier acceptance --seed $s --threads $threads --out $work/seed-$s ${extra[*]}"
    t=$({ time "$bin" --tier acceptance --seed "$s" --threads "$threads" --out "$work/seed-$s" "${extra[@]}" \
        > "$work/seed-$s.log" 2>&1; } 2>&1) || { echo "seed $s failed: see $work/seed-$s.log" >&2; exit 1; }
    read -r wall user sys <<< "$t"
    mkdir -p "$(dirname "$filed")"
    cp "$work/seed-$s/$fig/summary.json" "$filed"
    target/release/acceptance seal --from "$docs" --figure "$fig" --seed-folder "seed-$s" > /dev/null
    echo "seed $s$again wall $wall s cpu $user+$sys s" >> "$docs/times.log"
    target/release/acceptance stability --from "$docs" --figure "$fig" > "$docs/stability.md"
    echo "seed $s: filed (wall $wall s, cpu $user+$sys s)"
    if [ $commit = 1 ]; then
        git add "$filed" "$docs/seals.tsv" "$docs/times.log" "$docs/stability.md"
        [ -z "$name" ] || git add "$docs/cut.txt"
        git commit -q -m "$label acceptance seed $s$again" ||
            echo "seed $s: git commit failed; the seed is filed, commit it by hand" >&2
    fi
done
