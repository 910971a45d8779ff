#!/usr/bin/env bash
# Builds the conde_sim images with podman on a Debian 12 host that has no Docker engine and no
# image registry (the project's CI machines): the debian:bookworm base image is made locally with
# debootstrap from the host's Debian mirror, and every build runs with --pull=never, so no
# registry is contacted. Run as root from anywhere:
#
#   docker/podman_build.sh [--context DIR] [stage...]      stages: dev run gui (default: all three)
#   docker/podman_build.sh base                             only the base image
#
# Prints one line per stage: "built conde_sim:<stage> in <s> s, <MB> MB"; the image that had the
# tag before is removed unless a container still uses it (the layers it shares stay cached). The engine settings
# this host needs are written to $CONTAINERS_CONF; export the same CONTAINERS_CONF for every
# other podman call (podman run ...). docs/docker.md says why (runc, ulimits).
# Environment: IMAGE (conde_sim), CONTAINERS_CONF (/tmp/conde_sim-containers.conf),
# MIRROR / SECURITY_MIRROR (default: from the host's apt sources), BUILD_NICENESS (0; 19 builds
# at the lowest CPU priority on a shared machine, also when the container tests call this script).
set -euo pipefail

repo_root="$(cd "$(dirname "$0")/.." && pwd)"
context="$repo_root"
if [ "${1:-}" = "--context" ]; then context="$(cd "$2" && pwd)"; shift 2; fi
stages=("$@")
[ "${#stages[@]}" -gt 0 ] || stages=(dev run gui)
image="${IMAGE:-conde_sim}"
base_tag=docker.io/library/debian:bookworm   # what "FROM debian:bookworm" resolves to

command -v podman >/dev/null || { echo "podman_build.sh: error: podman is not installed (scripts/install_dependencies.sh containers)" >&2; exit 1; }

# Engine settings for this kind of host: Debian's crun refuses hybrid cgroup v1/v2 hosts (runc
# works), and without CAP_SYS_RESOURCE a container's rlimits must not exceed the caller's hard
# limits (podman caps its own nproc at 32768).
export CONTAINERS_CONF="${CONTAINERS_CONF:-/tmp/conde_sim-containers.conf}"
if [ ! -f "$CONTAINERS_CONF" ]; then
  nofile=$(ulimit -Hn); if [ "$nofile" = unlimited ] || [ "$nofile" -gt 1048576 ]; then nofile=1048576; fi
  nproc=$(ulimit -Hu); if [ "$nproc" = unlimited ] || [ "$nproc" -gt 32768 ]; then nproc=32768; fi
  runtime=runc; command -v runc >/dev/null || runtime=crun
  cat > "$CONTAINERS_CONF" <<EOF
[containers]
default_ulimits = ["nofile=$nofile:$nofile", "nproc=$nproc:$nproc"]
[engine]
runtime = "$runtime"
cgroup_manager = "cgroupfs"
EOF
fi

apt_uri() {  # first archive URI of the host's apt sources whose path matches $1 (deb822 or one-line)
  { grep -hsE '^URIs:' /etc/apt/sources.list.d/*.sources | awk '{print $2}' || true
    grep -hsE '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list | sed -E 's/\[[^]]*\] //' | awk '{print $2}' || true
  } 2>/dev/null | grep -E "$1" | head -n 1 || true
}

if ! podman image exists "$base_tag"; then
  command -v debootstrap >/dev/null || { echo "podman_build.sh: error: debootstrap is not installed" >&2; exit 1; }
  mirror="${MIRROR:-$(apt_uri '/debian/?$')}"; mirror="${mirror:-http://deb.debian.org/debian}"
  security="${SECURITY_MIRROR:-$(apt_uri '/debian-security/?$')}"; security="${security:-http://deb.debian.org/debian-security}"
  rootfs="$(mktemp -d /tmp/conde_sim-rootfs.XXXXXX)"
  trap 'rm -rf "$rootfs"' EXIT
  echo "podman_build.sh: making $base_tag with debootstrap from $mirror"
  started=$SECONDS
  nice -n "${BUILD_NICENESS:-0}" debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$rootfs.log" 2>&1 \
    || { tail -n 20 "$rootfs.log" >&2; echo "podman_build.sh: error: debootstrap failed (log: $rootfs.log)" >&2; exit 1; }
  rm -f "$rootfs.log" "$rootfs/etc/apt/sources.list" "$rootfs/etc/hostname" "$rootfs"/var/cache/apt/archives/*.deb
  rm -rf "$rootfs"/var/lib/apt/lists/*
  # The base trusts what the host trusts (e.g. a TLS-inspecting proxy's CA in front of PyPI):
  # update-ca-certificates adds this file when the images install ca-certificates.
  if [ -f /etc/ssl/certs/ca-certificates.crt ]; then
    mkdir -p "$rootfs/usr/local/share/ca-certificates"
    cp /etc/ssl/certs/ca-certificates.crt "$rootfs/usr/local/share/ca-certificates/build-host-trust.crt"
  fi
  # As in Docker Hub's debian images: dpkg skips fsync (a build layer is written at its end
  # anyway), apt fetches no translations.
  echo force-unsafe-io > "$rootfs/etc/dpkg/dpkg.cfg.d/docker-apt-speedup"
  echo 'Acquire::Languages "none";' > "$rootfs/etc/apt/apt.conf.d/docker-no-languages"
  mkdir -p "$rootfs/etc/apt/sources.list.d"
  cat > "$rootfs/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: $security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
  tar --numeric-owner -C "$rootfs" -c . | podman import --change 'CMD ["bash"]' - "$base_tag" >/dev/null
  rm -rf "$rootfs"
  echo "podman_build.sh: made $base_tag in $((SECONDS - started)) s"
fi

for stage in "${stages[@]}"; do
  [ "$stage" = base ] && continue
  previous_id=$(podman image inspect --format '{{.Id}}' "$image:$stage" 2>/dev/null || true)
  started=$SECONDS
  # --network=host: RUN steps reach the Debian mirror and PyPI without a bridge or firewall rules.
  # --format docker: as Docker builds it (podman's default OCI format drops SHELL).
  nice -n "${BUILD_NICENESS:-0}" podman build --pull=never --network=host --format docker \
    -f "$context/docker/Dockerfile" --target "$stage" \
    -t "$image:$stage" "$context"
  size_mb=$(( $(podman image inspect --format '{{.Size}}' "$image:$stage") / 1000000 ))
  echo "podman_build.sh: built $image:$stage in $((SECONDS - started)) s, $size_mb MB"
  current_id=$(podman image inspect --format '{{.Id}}' "$image:$stage")
  if [ -n "$previous_id" ] && [ "$previous_id" != "$current_id" ]; then
    podman rmi "$previous_id" >/dev/null 2>&1 || true
  fi
done
