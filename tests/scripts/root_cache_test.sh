#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Debian roots' cache (scripts/lib/root-cache.sh) against an archive served over HTTP on
# loopback by a real server: a key changes when the archive publishes (a new InRelease in any
# suite) or when the root's package list changes, and stays when nothing did or when a run fixed
# the archive's state at its start ($VPE_ROOT_ARCHIVE_STATE); sources in both
# apt formats are read; an unreadable archive gives no key; only a whole stored root is ever
# restored, and storing keeps one root per name.
#   root_cache_test.sh SOURCE_DIR
set -euo pipefail
source_dir=$1

work=$(mktemp -d /tmp/vpe-root-cache-test.XXXXXX)
server_pid=""
trap '[[ -n $server_pid ]] && kill $server_pid 2>/dev/null; rm -rf "$work"' EXIT
export VPE_ROOT_CACHE_DIR="$work/cache"
unset VPE_ROOT_CACHE_LOG  # not test.sh's report: these roots are the test's own
unset VPE_ROOT_ARCHIVE_STATE  # nor its archive's state: this test's archive is its own
source "$source_dir/scripts/lib/debian-root.sh"
source "$source_dir/scripts/lib/root-cache.sh"

fail() { echo "root_cache_test: FAILED: $*" >&2; exit 1; }

# The archive: two suites of one mirror, served by python's HTTP server on a free port.
mkdir -p "$work/archive/debian/dists/bookworm" "$work/archive/debian/dists/bookworm-updates"
echo "Suite: bookworm, published 1" >"$work/archive/debian/dists/bookworm/InRelease"
echo "Suite: bookworm-updates, published 1" >"$work/archive/debian/dists/bookworm-updates/InRelease"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 -m http.server "$port" --bind 127.0.0.1 --directory "$work/archive" >/dev/null 2>&1 &
server_pid=$!
for _ in $(seq 50); do
    python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/')" 2>/dev/null && break
    sleep 0.1
done
uri="http://127.0.0.1:$port/debian"
printf 'Types: deb\nURIs: %s\nSuites: bookworm bookworm-updates\nComponents: main\n' "$uri" >"$work/deb822.sources"
printf 'deb [arch=arm64] %s bookworm main\ndeb %s bookworm-updates main\n' "$uri" "$uri" >"$work/one-line.list"

key_a=$(root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev)
[[ "$key_a" =~ ^[0-9a-f]{24}$ ]] || fail "a key of 24 hex digits, got '$key_a'"
[[ "$(root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev)" == "$key_a" ]] ||
    fail "the same archive and packages give another key"
[[ "$(root_cache_key "$work/one-line.list" arm64 essential libdrm-dev)" == "$key_a" ]] ||
    fail "one-line sources of the same suites give another key than deb822"
[[ "$(root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev libgbm-dev)" != "$key_a" ]] ||
    fail "another package list keeps the key"
echo "Suite: bookworm-updates, published 2" >"$work/archive/debian/dists/bookworm-updates/InRelease"
key_b=$(root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev)
[[ "$key_b" != "$key_a" ]] || fail "the archive published and the key stayed"
# Within one run the state read at its start holds (scripts/test.sh), so that the roots made
# early and those made late agree even when the archive publishes meanwhile.
state_b=$(root_cache_archive_state "$work/deb822.sources")
echo "Suite: bookworm-updates, published 3" >"$work/archive/debian/dists/bookworm-updates/InRelease"
[[ "$(VPE_ROOT_ARCHIVE_STATE=$state_b root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev)" == "$key_b" ]] ||
    fail "the run's archive state was not used"
[[ "$(root_cache_key "$work/deb822.sources" arm64 essential libdrm-dev)" != "$key_b" ]] ||
    fail "the archive published again and the key stayed"

# An archive that cannot be read gives no key (the callers then make the root uncached).
printf 'deb http://127.0.0.1:%s/missing bookworm main\n' "$port" >"$work/missing.list"
if root_cache_key "$work/missing.list" arm64 >/dev/null 2>&1; then
    fail "a key for an archive that cannot be read"
fi

# Store, restore, replace; a partial copy is never restored.
mkdir -p "$work/root/etc"
echo first >"$work/root/etc/marker"
root_cache_restore sysroot "$key_a" "$work/restored" && fail "restored a root never stored"
root_cache_store sysroot "$key_a" "$work/root"
root_cache_restore sysroot "$key_a" "$work/restored" || fail "the stored root was not restored"
[[ "$(cat "$work/restored/etc/marker")" == first && ! -e "$work/restored/.vpe-root-complete" ]] ||
    fail "the restored root differs from the stored one"
root_cache_store sysroot "$key_b" "$work/root"
kept=("$VPE_ROOT_CACHE_DIR"/sysroot-*)
[[ ${#kept[@]} -eq 1 ]] || fail "more than one root kept for a name: ${kept[*]}"
root_cache_restore sysroot "$key_a" "$work/again" && fail "restored a root that was replaced"
rm -f "$VPE_ROOT_CACHE_DIR/sysroot-$key_b/.vpe-root-complete"
root_cache_restore sysroot "$key_b" "$work/again" && fail "restored a root whose copy did not finish"
[[ ! -e "$work/again" ]] || fail "a refused restore left a root behind"
echo "root_cache_test: passed"
