#!/usr/bin/env bash
# Installs irace (Debian's r-cran-irace, which pulls R) when it is missing, then prints where
# its command lives. Needs root (or sudo) for apt-get. Idempotent: does nothing when irace is
# already importable from R.
set -euo pipefail

have_irace() {
    command -v Rscript >/dev/null 2>&1 &&
        Rscript -e 'quit(status = if (requireNamespace("irace", quietly = TRUE)) 0 else 1)' \
            >/dev/null 2>&1
}

if ! have_irace; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null 2>&1; then
            SUDO="sudo"
        else
            echo "install-irace: not root and no sudo; install r-cran-irace by hand" >&2
            exit 1
        fi
    fi
    echo "install-irace: installing r-cran-irace with apt-get" >&2
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -q
    $SUDO apt-get install -y -q --no-install-recommends r-cran-irace
fi

if ! have_irace; then
    echo "install-irace: irace is still not importable from R" >&2
    exit 1
fi
Rscript -e 'cat("irace", as.character(packageVersion("irace")), "at", system.file("bin", "irace", package = "irace"), "\n")'
