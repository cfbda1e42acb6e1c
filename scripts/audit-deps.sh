#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Dependency audit: every file a build found on the system must belong to a Debian package
# that scripts/install-deps.sh names, or else a fresh machine cannot build what this one did.
#
#   scripts/audit-deps.sh query BUILD_DIR           before configuring: ask CMake's file API
#   scripts/audit-deps.sh check BUILD_DIR           after configuring: CMake package configs and
#                                                   find modules, find_path/find_library hits,
#                                                   pkg-config .pc files, the include
#                                                   directories and libraries of every target
#   scripts/audit-deps.sh check --headers BUILD_DIR after building: also every system header
#                                                   the compiler read (ninja's dependency log)
#   ... check [--headers] [--named FILE] BUILD_DIR  packages from FILE, one per line, instead of
#                                                   install-deps.sh --list --test (for tests)
#   ... check [--headers] --sysroot DIR BUILD_DIR   a cross build: files under DIR belong to
#                                                   DIR's own Debian packages, which must be
#                                                   install-deps.sh --list-arm64-root or their
#                                                   dependencies; the rest to this machine's, with
#                                                   the --arm64 set named too
#
# A file passes when its package is named there or is a dependency of one that is (what apt
# installs with it: libc6-dev, cmake-data, a -dev package's runtime library). A failure prints
# one line per missing package, naming its package config (or another of its files), and
# exits 1.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

usage() { sed -n '5,19p' "$0" >&2; exit 2; }
[[ $# -ge 2 ]] || usage
mode=$1; shift
headers=0
named=""
sysroot=""
while [[ $# -gt 1 ]]; do
    case "$1" in
        --headers) headers=1 ;;
        --named) named=$2; shift ;;
        --sysroot) sysroot=$(realpath -m "$2"); shift ;;
        *) usage ;;
    esac
    shift
done
build=${1:?}
query="$build/.cmake/api/v1/query"
reply="$build/.cmake/api/v1/reply"

if [[ "$mode" == query ]]; then
    mkdir -p "$query"
    touch "$query/codemodel-v2" "$query/cache-v2" "$query/cmakeFiles-v1"
    exit 0
fi
[[ "$mode" == check ]] || usage
command -v jq >/dev/null || { echo "audit-deps: jq is missing (scripts/install-deps.sh --test)" >&2; exit 2; }
index=$(ls -1 "$reply"/index-*.json 2>/dev/null | tail -n 1)
[[ -n "$index" ]] || { echo "audit-deps: $build: no CMake file-API reply; run 'audit-deps.sh query $build' before configuring" >&2; exit 2; }

reply_file() { # KIND: the reply object of that kind
    local name
    name=$(jq -r --arg kind "$1" '.objects[] | select(.kind == $kind) | .jsonFile' "$index")
    [[ -n "$name" ]] || { echo "audit-deps: $index: no '$1' object" >&2; exit 2; }
    echo "$reply/$name"
}

# The project's own files are not the system's: the source tree the build was configured from
# (which need not be this script's, e.g. an older commit's tree audited with this script).
source=$(jq -r '.paths.source' "$(reply_file codemodel)")
# The project's own files are dropped, except a sysroot's, which may sit in the build folder.
own_files_dropped() {
    if [[ -n "$sysroot" ]]; then
        awk -v r="$sysroot/" -v own="^($(realpath -m "$source")|$(realpath -m "$build"))(/|$)" \
            'index($0, r) == 1 || $0 !~ own'
    else
        grep -vE "^($(realpath -m "$source")|$(realpath -m "$build"))(/|$)"
    fi
}
found=$(mktemp)
trap 'rm -f "$found" "$found".*' EXIT
{
    # CMake files read from outside the source and build trees: package configs, find modules
    # (CMake's own modules are the toolchain's and pass below).
    # A sysroot inside the source tree is not "external" to CMake, but its files are the system's.
    configs=$(jq -r --arg root "${sysroot:+$sysroot/}" '.inputs[]
        | select((.isExternal == true or ($root != "" and (.path | startswith($root))))
                 and (.isCMake // false) == false) | .path' "$(reply_file cmakeFiles)")
    echo "$configs"
    # Every file the packages' exported targets name (their libraries, headers and programs:
    # IMPORTED_LOCATION and the existence checks of *-targets-<config>.cmake), which CMake
    # requires to exist even when vpe links none of them: glslang's config fails without
    # glslangValidator, from a package glslang-dev does not depend on. Debian installs every
    # such package under /usr, its ${_IMPORT_PREFIX}.
    { grep -E '[Tt]argets-[A-Za-z]+\.cmake$' <<<"$configs" || true; } | while read -r exported; do
        root=""
        [[ -n "$sysroot" && "$exported" == "$sysroot"/* ]] && root=$sysroot
        import_prefix=$root/
        [[ "$exported" == "$root"/usr/* ]] && import_prefix=$root/usr
        grep -o '"\${_IMPORT_PREFIX}/[^"]*"' "$exported" | tr -d '"' | tr ';' '\n' |
            sed "s|\${_IMPORT_PREFIX}|$import_prefix|" || true
    done
    # find_path / find_library / find_file / find_program results, pkg-config's library hits.
    # CMAKE_* entries are CMake's own settings (compilers, install prefix), not things found.
    jq -r '.entries[] | select((.type == "FILEPATH" or .type == "PATH") and (.name | startswith("CMAKE_") | not))
           | .value' "$(reply_file cache)" |
        tr ';' '\n'
    # pkg-config modules asked for by pkg_check_modules: their .pc files.
    jq -r '.entries[] | select(.name | startswith("__pkg_config_arguments_")) | .value' \
        "$(reply_file cache)" | tr ';' '\n' |
        grep -vE '^(REQUIRED|QUIET|IMPORTED_TARGET|GLOBAL|NO_CMAKE_PATH|NO_CMAKE_ENVIRONMENT_PATH)$' |
        sed 's/[<>=].*//' | sort -u | while read -r module; do
            [[ -n "$module" ]] && pkg-config --path "$module" 2>/dev/null || true
        done
    # Every target's include directories and the libraries on its link line.
    codemodel=$(reply_file codemodel)
    for target in $(jq -r '.configurations[].targets[].jsonFile' "$codemodel"); do
        jq -r '(.compileGroups // [])[].includes // [] | .[].path' "$reply/$target"
        jq -r '(.link.commandFragments // [])[] | select(.role == "libraries") | .fragment' \
            "$reply/$target" | tr ' ' '\n' | grep '^/' || true
    done
    if [[ $headers -eq 1 ]]; then
        command -v ninja >/dev/null && [[ -f "$build/.ninja_deps" ]] ||
            { echo "audit-deps: $build: no ninja dependency log to read headers from" >&2; exit 2; }
        ninja -C "$build" -t deps | sed -n 's/^    \(\/.*\)$/\1/p'
    fi
} | grep '^/' | own_files_dropped | grep -vE '^/(tmp|proc|dev)/' | sort -u >"$found"

# Which Debian package owns each file, asked in batches. dpkg records some files under / and
# some under /usr, and may know a -dev package's symlink only by its target: a file dpkg does
# not know is asked again under those names.
dpkg_owners() { # stdin: "query<TAB>path"; stdout: "path<TAB>owners" for the queries dpkg knows
    local map
    map=$(mktemp -p "$(dirname "$found")")
    cat >"$map"
    # A sysroot's dpkg knows its files by their paths inside it.
    cut -f1 "$map" | sed "s|^$prefix/|/|" |
        xargs -r -d '\n' sh -c 'dpkg --root="$0" -S "$@" 2>/dev/null; true' "${prefix:-/}" |
        sed "s|: /|: $prefix/|" |
        sed '/^diversion/d' | sed -n 's/^\(.*\): \(\/.*\)$/\2\t\1/p' |
        awk -F'\t' 'NR == FNR {path[$1] = $2; next} ($1 in path) {print path[$1] "\t" $2}' "$map" -
    rm -f "$map"
}
# audit LIST NAMED PREFIX: checks the files in LIST against the packages in NAMED and their
# dependencies, in the dpkg database of the root at PREFIX ("" for this machine).
audit() {
    local list=$1 named_list=$2 prefix=$3 where=$build${3:+ (sysroot $3)}
    while read -r path; do [[ -e "$path" ]] && printf '%s\t%s\n' "$path" "$path"; done <"$list" |
        dpkg_owners >"$list.owners"
    awk -F'\t' 'NR == FNR {known[$1] = 1; next} !($0 in known)' "$list.owners" "$list" |
        while read -r path; do
            [[ -e "$path" ]] || continue
            inner=${path#"$prefix"}
            [[ "$inner" == /usr/* ]] && printf '%s\t%s\n' "$prefix${inner#/usr}" "$path"
            [[ -L "$path" ]] && printf '%s\t%s\n' "$(readlink -f "$path")" "$path"
            true
        done | dpkg_owners | sort -u -t$'\t' -k1,1 >>"$list.owners"
    while read -r path; do [[ -e "$path" ]] && echo "$path"; done <"$list" >"$list.existing"

    # Acceptable packages: the ones named and what they depend on, which is exactly what
    # `apt-get install --no-install-recommends` of the named list puts on a fresh machine. A
    # package that was installed by hand (like libopencv-dev once) is in neither.
    dpkg-query --admindir="${prefix:-}/var/lib/dpkg" -W -f='${db:Status-Abbrev}\t${Package}\t${Depends},${Pre-Depends}\t${Provides}\n' |
        awk -F'\t' '
            function name(s) { sub(/\|.*/, "", s); sub(/\(.*\)/, "", s); gsub(/ /, "", s); sub(/:.*/, "", s); return s }
            NR == FNR { queue[++tail] = $1; next }
            $1 ~ /^ii/ {
                depends[$2] = $3
                n = split($4, v, ","); for (i = 1; i <= n; i++) if (name(v[i]) != "") provider[name(v[i])] = $2
            }
            END {
                # Breadth-first over Depends and Pre-Depends, first alternatives (what apt picks on
                # a fresh machine), virtual names resolved to the installed package providing them.
                for (head = 1; head <= tail; head++) {
                    p = queue[head]
                    if (!(p in depends) && (p in provider)) p = provider[p]
                    if (p in seen) continue
                    seen[p] = 1; print p
                    n = split(depends[p], d, ",")
                    for (i = 1; i <= n; i++) if (name(d[i]) != "") queue[++tail] = name(d[i])
                }
            }' "$named_list" - >"$list.allowed"

    awk -F'\t' -v build="$where" '
        FILENAME == ARGV[1] { allowed[$1] = 1; next }
        FILENAME == ARGV[2] { owners[$1] = $2; next }
        {
            count++
            list = ($0 in owners) ? owners[$0] : "(no Debian package)"
            n = split(list, o, ", *"); ok = 0
            for (i = 1; i <= n; i++) { sub(/:.*/, "", o[i]); if (o[i] in allowed) ok = 1 }
            if (ok) next
            # One line per package, naming its most telling file: a package config or .pc file.
            files[list]++
            telling = ($0 ~ /(Config\.cmake|-config\.cmake|\.pc)$/)
            if (!(list in shown) || (telling && !shown_telling[list])) { shown[list] = $0; shown_telling[list] = telling }
        }
        END {
            for (list in shown) {
                more = files[list] > 1 ? sprintf(" (and %d more of its files)", files[list] - 1) : ""
                print "audit-deps: " shown[list] " ← " list more ", which scripts/install-deps.sh does not name" > "/dev/stderr"
                bad = 1
            }
            if (!bad) print "audit-deps: " build ": all " count " system files the build found come from named packages" > "/dev/stderr"
            exit bad
        }' "$list.allowed" "$list.owners" "$list.existing"
}

if [[ -n "$sysroot" ]]; then
    # A cross build: the sysroot's files against its own packages, the rest (the cross
    # compiler, flatc, CMake's modules) against this machine's.
    grep -F "$sysroot/" "$found" >"$found.target" || true
    grep -vF "$sysroot/" "$found" >"$found.host" || true
    [[ -n "$named" ]] && cp "$named" "$found.named.host" ||
        "$here/install-deps.sh" --list --test --arm64 >"$found.named.host"
    "$here/install-deps.sh" --list-arm64-root >"$found.named.target"
    status=0
    prefix="" audit "$found.host" "$found.named.host" "" || status=1
    prefix="$sysroot" audit "$found.target" "$found.named.target" "$sysroot" || status=1
    exit $status
fi
if [[ -n "$named" ]]; then cp "$named" "$found.named"; else "$here/install-deps.sh" --list --test >"$found.named"; fi
prefix="" audit "$found" "$found.named" ""
