# SPDX-License-Identifier: MIT
# Sourced by scripts/test.sh: what a run took, kept as it goes and printed when it ends (even
# when it fails), so that CI's budget (90 minutes on 2 cores) is watched on every run:
#   - each stage's seconds and the total, with a warning above 45 minutes;
#   - whether the compile cache was warm or cold (ccache's hits during this run), and which
#     Debian roots came from their cache;
#   - each build's compile time (CPU seconds summed from ninja's log) and its compiles;
#   - the 25 slowest tests of each stage (from ctest's own lines, kept in build/test-run/).
# Nothing here decides whether the run passes.

test_run_dir=build/test-run
test_run_warn_seconds=2700
test_run_started=$SECONDS
test_run_stage_started=$SECONDS
test_run_stage_names=()
test_run_stage_seconds=()
test_run_presets=()
test_run_current_stage=""

# ccache's counters as "hits misses", read from whatever cache CCACHE_DIR names.
test_run_cache_counts() {
    ccache --print-stats 2>/dev/null | awk '
        $1 == "direct_cache_hit" || $1 == "preprocessed_cache_hit" { hits += $2 }
        $1 == "cache_miss" { misses += $2 }
        END { printf "%d %d\n", hits, misses }'
}

# test_run_begin: at the start of the run, after the cache is chosen.
test_run_begin() {
    rm -rf "$test_run_dir"
    mkdir -p "$test_run_dir"
    VPE_ROOT_CACHE_LOG=$(realpath -m "$test_run_dir/roots.txt")  # not a ctest log
    export VPE_ROOT_CACHE_LOG
    read -r test_run_hits_before test_run_misses_before < <(test_run_cache_counts)
}

# test_run_stage NAME: ends the stage before (its seconds kept) and begins NAME.
test_run_stage() {
    test_run_close_stage
    test_run_current_stage=$1
    printf '\n== [%d s] %s\n' $((SECONDS - test_run_started)) "$1" >&2
}

test_run_close_stage() {
    if [[ -n $test_run_current_stage ]]; then
        test_run_stage_names+=("$test_run_current_stage")
        test_run_stage_seconds+=($((SECONDS - test_run_stage_started)))
        printf '== stage took %d s: %s\n' $((SECONDS - test_run_stage_started)) \
            "$test_run_current_stage" >&2
    fi
    test_run_current_stage=""
    test_run_stage_started=$SECONDS
}

# test_run_built PRESET: a build folder whose compile is reported at the end.
test_run_built() { test_run_presets+=("$1"); }

# test_run_ctest LOG ARGS...: ctest ARGS, its lines also kept in build/test-run/LOG.log.
test_run_ctest() {
    local log=$1
    shift
    ctest "$@" 2>&1 | tee -a "$test_run_dir/$log.log"
}

# The 25 slowest tests of one ctest log, as "seconds  status  name".
test_run_slowest() {
    sed -nE 's/^ *[0-9]+\/[0-9]+ +Test +#[0-9]+: +([^ ].*[^ .]) +[.]* *[*]*([A-Za-z][A-Za-z ]*[A-Za-z]) +([0-9.]+) +sec.*/\3|\2|\1/p' "$1" |
        sort -t'|' -k1,1gr | awk -F'|' 'NR <= 25 { printf "  %8.1f s  %-8s %s\n", $1, $2, $3 }'
}

# Compile CPU seconds of one build folder: the sum of every step ninja timed (its log keeps
# each step's start and end in ms; with -j N they overlap, so this is core-seconds) and the
# number of compiles among them.
test_run_compile_seconds() {
    local log="build/$1/.ninja_log"
    [[ -f $log ]] || { echo "-"; return; }
    awk '!/^#/ { total += ($2 - $1) / 1000; if ($4 ~ /\.o$/) objects++ }
        END { printf "%.0f core-s, %d objects", total, objects }' "$log"
}

# test_run_summary STATUS: the report, printed last.
test_run_summary() {
    local status=$1 total=$((SECONDS - test_run_started)) i log hits misses
    test_run_close_stage
    {
        echo
        echo "== the 25 slowest tests of each stage (build/test-run/*.log)"
        for log in "$test_run_dir"/*.log; do
            [[ -f $log ]] || continue
            echo "$(basename "$log" .log):"
            test_run_slowest "$log"
        done
        echo
        echo "== compile, per build (ninja's log; cores overlap)"
        for i in "${test_run_presets[@]}"; do
            printf '  %-16s %s\n' "$i" "$(test_run_compile_seconds "$i")"
        done
        echo
        echo "== test.sh, stage by stage (exit $status)"
        printf '| %-62s | %7s |\n' stage seconds
        printf '|%s|%s|\n' "$(printf -- '-%.0s' {1..64})" "$(printf -- '-%.0s' {1..9})"
        for i in "${!test_run_stage_names[@]}"; do
            printf '| %-62s | %7d |\n' "${test_run_stage_names[i]}" "${test_run_stage_seconds[i]}"
        done
        printf '| %-62s | %7d |\n' "total" "$total"
        read -r hits misses < <(test_run_cache_counts)
        hits=$((hits - test_run_hits_before))
        misses=$((misses - test_run_misses_before))
        local compiles=$((hits + misses)) kind=cold percent=0
        ((compiles > 0)) && percent=$((100 * hits / compiles))
        # A cold run hits too: the device package takes the release build's objects (about 11%).
        ((percent >= 90)) && kind=warm
        ((percent >= 50 && percent < 90)) && kind="partly warm"
        echo "compile cache ($CCACHE_DIR): $hits hits, $misses misses of $compiles compiles" \
            "($percent%): a $kind run"
        # The Debian roots (scripts/lib/root-cache.sh logs each one it restored or made).
        if [[ -s "$VPE_ROOT_CACHE_LOG" ]]; then
            echo "Debian roots ($(root_cache_dir)):" \
                "$(grep -c '^restored ' "$VPE_ROOT_CACHE_LOG") from the cache," \
                "$(grep -c '^made ' "$VPE_ROOT_CACHE_LOG") made by mmdebstrap" \
                "($(awk '{ print $2 ": " $1 }' "$VPE_ROOT_CACHE_LOG" | paste -sd, - | sed 's/,/, /g'))"
        fi
        if ((total > test_run_warn_seconds)); then
            echo "WARNING: test.sh took $total s, over $test_run_warn_seconds s (45 minutes):" \
                "CI allows 5,400 s; find what grew (the tables above)"
        fi
    } >&2
}
