#!/usr/bin/env bash
# Mutation testing of the safety core: cargo-mutants changes the code one small way at
# a time (a `>` into `>=`, a function that returns None) and runs the tests that cover
# it. A change that no test notices ("missed") is a rule no test holds.
#
#   scripts/mutants.sh                      the whole safety core (about an hour or more)
#   scripts/mutants.sh FILE...              those files only
#   scripts/mutants.sh --changed [FILE...]  only lines changed since the base (below)
#   scripts/mutants.sh --shard 2/4 ...      one part of a long run (as cargo-mutants')
#   scripts/mutants.sh --list [FILE...]     name the mutants, run nothing
#   scripts/mutants.sh --table              the last results per file, as a table
#
# --base REV sets the base of --changed (default: the branch's upstream if it has one,
# else HEAD, that is the changes not yet committed). Arguments after `--` go to
# cargo-mutants as they are.
#
# Each mutant runs the tests of the crate it is in, without doc-tests: for the safety
# core (core/) that is the core's unit and lockstep tests, a few seconds each. Results
# go to target/mutants-GROUP/mutants.out; dependencies are built once into
# target/mutants and kept.
# At the end every missed mutant is looked up in docs/testing.md: one it does not
# explain makes the script fail. Not run by CI: see docs/testing.md for when to run it.
set -euo pipefail
cd "$(dirname "$0")/.."

# The safety core: the supervisor (its tick, rules, regulators, end switches), the
# fault checks, the measurements, the steering law and the row filter's gate.
safety_core=(
    'core/src/supervisor/*.rs'
    'core/src/faults/*.rs'
    core/src/state/measure.rs
    core/src/steer/law.rs
    core/src/steer/filter_gate.rs
)

files=()
changed=false
base=""
list=false
table_only=false
passthrough=()
while [ $# -gt 0 ]; do
    case "$1" in
    --changed) changed=true ;;
    --base)
        base="${2:?--base needs a git revision}"
        shift
        ;;
    --shard)
        passthrough+=(--shard "${2:?--shard needs K/N, for example 1/4}")
        shift
        ;;
    --list) list=true ;;
    --table) table_only=true ;;
    -h | --help)
        sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'
        exit 0
        ;;
    --)
        shift
        passthrough+=("$@")
        break
        ;;
    -*)
        echo "mutants.sh: unknown option $1 (see --help)" >&2
        exit 1
        ;;
    *)
        f="$1"
        # Paths from before the core became a crate of its own (src/supervisor/...)
        # still work: the file is looked for under core/ and hw/.
        if [ ! -e "$f" ]; then
            for crate in core hw; do
                if [ -e "$crate/$f" ]; then
                    echo "mutants.sh: $f is now $crate/$f" >&2
                    f="$crate/$f"
                    break
                fi
            done
        fi
        [ -e "$f" ] || {
            echo "mutants.sh: no file $1 (give paths from the project's root)" >&2
            exit 1
        }
        files+=("$f")
        ;;
    esac
    shift
done
[ ${#files[@]} -gt 0 ] || files=("${safety_core[@]}")

if ! cargo mutants --version >/dev/null 2>&1; then
    echo "mutants.sh: cargo-mutants is missing; installing it (a few minutes)" >&2
    cargo install --locked cargo-mutants
fi

diff_args=()
if $changed; then
    if [ -z "$base" ]; then
        base=$(git rev-parse --abbrev-ref --symbolic-full-name '@{upstream}' 2>/dev/null || echo HEAD)
    fi
    diff_file=$(mktemp)
    trap 'rm -f "$diff_file"' EXIT
    git diff "$base" -- . >"$diff_file"
    if [ ! -s "$diff_file" ]; then
        echo "mutants.sh: nothing changed since $base"
        exit 0
    fi
    echo "mutants.sh: only the lines changed since $base" >&2
    diff_args=(--in-diff "$diff_file")
fi

# The files in groups by the tests that can see them. Each group skips the core's
# slowest tests that exercise none of its files: the camera decoder's property tests,
# the recorder's files and the steering bound's model for all of the core, and the row
# filter's own unit tests outside steer/. Skipped so, a mutant's tests take 2 to 5 s,
# not 12.
steer=()
core=()
other=()
for f in "${files[@]}"; do
    case "$f" in
    core/src/steer/*) steer+=("$f") ;;
    core/*) core+=("$f") ;;
    *) other+=("$f") ;;
    esac
done
skip_core=(decoder_props record::tests bench::bound::)

run_group() {
    local name="$1"
    shift
    local -a skips=() args=(--workspace --cargo-test-arg=--tests)
    while [ "$1" != -- ]; do
        skips+=("$1")
        shift
    done
    shift
    for f in "$@"; do args+=(--file "$f"); done
    if [ ${#skips[@]} -gt 0 ]; then
        args+=(--cargo-test-arg=--)
        for test in "${skips[@]}"; do args+=(--cargo-test-arg=--skip "--cargo-test-arg=$test"); done
    fi
    args+=("${diff_args[@]}")
    if $list; then
        cargo mutants --list "${args[@]}" "${passthrough[@]}"
        return
    fi
    echo "mutants.sh: $name: $*" >&2
    local rc=0
    # One job at a time shares one target directory, kept between runs; with `-- -j N`
    # each job builds in its own copy (cargo would make them wait for each other).
    local -a target=(env CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target/mutants}")
    case " ${passthrough[*]} " in *" -j"* | *" --jobs"*) target=(env) ;; esac
    "${target[@]}" cargo mutants "${args[@]}" --output "target/mutants-$name" \
        "${passthrough[@]}" || rc=$?
    # cargo-mutants: 0 all caught, 2 some missed, 3 some timed out; others are its errors.
    case $rc in
    0 | 2 | 3) outs+=("target/mutants-$name/mutants.out") ;;
    *)
        echo "mutants.sh: cargo-mutants failed (exit $rc); see target/mutants-$name/mutants.out/debug.log" >&2
        exit "$rc"
        ;;
    esac
}

# The results per file, as docs/testing.md's table: mutants, caught, missed,
# unviable and timed out (timeouts count as caught: the tests did not pass).
table() {
    echo "| file | mutants | caught | missed | unviable | timeouts |"
    echo "|---|---|---|---|---|---|"
    for kind in caught missed unviable timeout; do
        cat "${outs[@]/%//$kind.txt}" 2>/dev/null | sed -E "s/:[0-9]+:[0-9]+: .*/ $kind/"
    done | awk '{ n[$1, $2]++; files[$1] = 1 }
        END {
            for (f in files) {
                c = n[f, "caught"] + 0; m = n[f, "missed"] + 0
                u = n[f, "unviable"] + 0; t = n[f, "timeout"] + 0
                printf "| `%s` | %d | %d | %d | %d | %d |\n", f, c + m + u + t, c, m, u, t
            }
        }' | sort
}

outs=()
if $table_only; then
    for d in target/mutants-*/mutants.out; do [ -d "$d" ] && outs+=("$d"); done
    [ ${#outs[@]} -gt 0 ] || { echo "mutants.sh: no results yet in target/mutants-*" >&2; exit 1; }
    table
    exit 0
fi
[ ${#steer[@]} -eq 0 ] || run_group steer "${skip_core[@]}" -- "${steer[@]}"
[ ${#core[@]} -eq 0 ] || run_group core "${skip_core[@]}" steer::filter::tests -- "${core[@]}"
[ ${#other[@]} -eq 0 ] || run_group other -- "${other[@]}"
$list && exit 0

# Each missed mutant by its name without the line and column (they move with edits),
# as docs/testing.md writes it between backticks.
count() { cat "${outs[@]/%//$1.txt}" 2>/dev/null | grep -c . || true; }
unexplained=0
while IFS= read -r line; do
    [ -n "$line" ] || continue
    name=$(printf '%s\n' "$line" | sed -E 's/^([^:]+):[0-9]+:[0-9]+: /\1: /')
    if grep -qF -- "\`$name\`" docs/testing.md; then
        echo "missed, explained in docs/testing.md: $line"
    else
        echo "MISSED, NOT EXPLAINED: $line"
        unexplained=$((unexplained + 1))
    fi
done < <(cat "${outs[@]/%//missed.txt}" 2>/dev/null)

table
echo "caught $(count caught), missed $(count missed) ($unexplained not explained)," \
    "unviable $(count unviable), timeouts $(count timeout); details in ${outs[*]}"
[ "$unexplained" -eq 0 ]
