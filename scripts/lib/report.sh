# SPDX-License-Identifier: MIT
# Shared by the report scripts (sourced from the repository root once their arguments are read):
# the set-up they all begin with, and their progress and JSON helpers.
source scripts/lib/vpe.sh

# report_options NAME OPTION... -- ARG...: each "--OPTION VALUE" among the ARGs sets the variable
# OPTION (its dashes as underscores: --load-seconds sets $load_seconds); anything else stops the
# script, exit status 2, with "NAME: unknown argument '...'".
report_options() {
    local name=$1 options=" "
    shift
    while [[ "$1" != -- ]]; do
        options+="$1 "
        shift
    done
    shift
    while (($#)); do
        if [[ "$1" != --* || "$options" != *" ${1#--} "* || $# -lt 2 ]]; then
            echo "$name: unknown argument '$1'" >&2
            exit 2
        fi
        local option=${1#--}
        printf -v "${option//-/_}" '%s' "$2"
        shift 2
    done
}

# start_report [--keep-out]: the test tools (jq, oiiotool, ...) installed, vpe and vpe-player
# built ($vpe, $player), and $out an absolute path to an empty folder; with --keep-out the
# folder keeps what it holds (a folder of the docs' pictures).
start_report() {
    scripts/install-deps.sh --test
    build_vpe >&2
    out=$(realpath -m "$out")
    [[ "${1-}" == --keep-out ]] || rm -rf "$out"
    mkdir -p "$out"
}

# step TEXT: a heading on stderr between the steps' own output (stdout is the report's), with
# the seconds since the script started, so that a long run shows where its time goes.
step() { printf '\n== [%d s] %s\n' "$SECONDS" "$*" >&2; }

# json FILTER FILE: one value of a JSON report, as text.
json() { jq -r "$1" "$2"; }
