#!/usr/bin/env bash
# Opens two pages of brdf-sls in headless Chromium, as a reader would: the report of a results
# folder (written by `run`) and a comparison of that folder with a second, small run of the
# same experiment under another kernel. Fails when a page logs a console error, when a figure
# or table of the page is missing from the browser's DOM, or when its screenshot is blank.
#
# Usage: scripts/ci-browser.sh [RESULTS_DIR] [BRDF_SLS_BINARY] [WORK_DIR]
#   defaults: runs/default, target/release/brdf-sls, runs/browser
# Installs Debian's chromium when /usr/bin/chromium is missing (needs root, as in CI).
set -euo pipefail

results=${1:-runs/default}
bin=${2:-target/release/brdf-sls}
work=${3:-runs/browser}
mkdir -p "$work"
work=$(cd "$work" && pwd)

if [[ ! -x /usr/bin/chromium ]]; then
    apt-get update
    apt-get install -y chromium
fi

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT

# The flags a closed network needs: no sandbox (root), no GPU, no first-run or background
# traffic; console messages go to standard error.
chromium_run() {
    /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --user-data-dir="$profile" --enable-logging=stderr --v=0 "$@"
}

# Console messages of a page (errors among them) as Chromium logs them.
console_lines() {
    grep -E ':CONSOLE[:(]|Uncaught' "$1" || true
}

# Runs scripts/page-checks.js on a copy of a page in a window of $3 (WIDTHxHEIGHT): the page
# no wider than the window, a report's summary in the first screen, no legend over a plot, one
# colour per configuration, no number cell over 8 significant digits. $1 = the HTML file,
# $2 = a short name for the outputs.
layout_check() {
    local page name=$2 size=$3 probe dom
    page=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
    probe="$(dirname "$page")/.$name-$size.checks.html"
    dom="$work/$name-$size.checks.dom.html"
    # The page carries no script: the checks run on a copy beside it (same relative links).
    { head -n -2 "$page"; echo '<script>'; cat "$(dirname "$0")/page-checks.js"; echo '</script>'; tail -n 2 "$page"; } > "$probe"
    chromium_run --dump-dom --window-size="${size/x/,}" "file://$probe" > "$dom" 2>> "$work/$name.console.log"
    rm -f "$probe"
    # The checks' report: the text of <pre id="page-checks">, one line each.
    sed -n '/<pre id="page-checks">/,/<\/pre>/p' "$dom" \
        | sed 's/.*<pre id="page-checks">//; s#</pre>.*##' > "$dom.report"
    if ! grep -q '^checked: ' "$dom.report"; then
        echo "error: $name at $size: the layout checks did not run" >&2
        return 1
    fi
    grep '^checked: ' "$dom.report" | sed "s/^/$name at $size: /"
    if grep -q '^FAIL: ' "$dom.report"; then
        grep '^FAIL: ' "$dom.report" | sed "s/^/error: $name at $size: /" >&2
        return 1
    fi
}

# Checks one page: no console message, every figure and table in the DOM, a screenshot that
# is not blank, and the layout checks at 1280x800 and 800x800. $1 = the HTML file, $2 = a
# short name for the outputs.
check_page() {
    local page name dom log png expected_fig expected_tab got_fig got_tab got_svg
    page=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
    name=$2
    dom="$work/$name.dom.html"
    log="$work/$name.console.log"
    png="$work/$name.png"
    test -s "$page" || { echo "error: $page is missing or empty" >&2; return 1; }
    chromium_run --dump-dom "file://$page" > "$dom" 2> "$log"
    if [[ -n "$(console_lines "$log")" ]]; then
        echo "error: $name: console messages:" >&2
        console_lines "$log" >&2
        return 1
    fi
    expected_fig=$(grep -o '<figure class="chart"' "$page" | wc -l)
    expected_tab=$(grep -o '<table class=' "$page" | wc -l)
    got_fig=$(grep -o '<figure class="chart"' "$dom" | wc -l)
    got_tab=$(grep -o '<table class=' "$dom" | wc -l)
    got_svg=$(grep -o '<svg role="img"' "$dom" | wc -l)
    if [[ "$expected_fig" -lt 1 || "$got_fig" -ne "$expected_fig" || "$got_svg" -ne "$expected_fig" ]]; then
        echo "error: $name: $expected_fig figures in the page, $got_fig figures and $got_svg SVGs in the DOM" >&2
        return 1
    fi
    if [[ "$expected_tab" -lt 1 || "$got_tab" -ne "$expected_tab" ]]; then
        echo "error: $name: $expected_tab tables in the page, $got_tab in the DOM" >&2
        return 1
    fi
    chromium_run --screenshot="$png" --window-size=1280,2000 "file://$page" 2>> "$log" >/dev/null
    python3 "$(dirname "$0")/png-colours.py" "$png" --min-colours 16 --min-ink 0.01
    layout_check "$page" "$name" 1280x800
    layout_check "$page" "$name" 800x800
    echo "$name: $got_fig figures, $got_tab tables, no console messages; screenshot $png"
}

# The console check must see a real console error: a probe page logs one.
probe="$work/probe.html"
echo '<!DOCTYPE html><html><body><script>console.error("probe-error")</script></body></html>' > "$probe"
chromium_run --dump-dom "file://$probe" > /dev/null 2> "$work/probe.log"
if ! console_lines "$work/probe.log" | grep -q probe-error; then
    echo "error: a console error of a probe page was not seen; the console check would be blind" >&2
    exit 1
fi

# The layout checks must see what they look for: a copy of the report broken five ways (the
# summary pushed below the first screen, a legend moved over its plot, a configuration's
# colour changed in one figure, a number cell with 17 digits, a 2000-pixel-wide block) fails
# each of them.
broken="$(dirname "$results/report.html")/.broken-report.html"
sed -e '0,/<p class="tcap">/s//<div style="height: 3000px"><\/div><p class="tcap">/' \
    -e '0,/<ul class="legend">/s//<ul class="legend" style="position: relative; top: -300px">/' \
    -e '0,/stroke="#0072b2"/s//stroke="#d55e00"/' \
    -e '0,/<td class="num">/s//<td class="num">0.10053773452859387 /' \
    -e 's#<p class="note">Written by#<div style="width: 2000px">wide</div>&#' \
    "$results/report.html" > "$broken"
if layout_check "$broken" broken 1280x800 2> "$work/broken.err"; then
    rm -f "$broken"
    echo "error: the layout checks passed a broken page; they would be blind" >&2
    exit 1
fi
rm -f "$broken"
for want in "below the first screen" "legend overlaps" "is #d55e00 in figure" \
    "17 significant digits" "px wide in a window"; do
    if ! grep -q "$want" "$work/broken.err"; then
        echo "error: the layout checks missed \"$want\" on a broken page:" >&2
        cat "$work/broken.err" >&2
        exit 1
    fi
done
echo "the layout checks see a summary below the fold, a legend over a plot, a changed colour, a long number and a wide page"

check_page "$results/report.html" report

# The same experiment again into another folder, under another kernel and with fewer trials.
"$bin" run --out "$work/portable" --kernel portable --limit 30 --no-plots --progress quiet --fresh
status=0
"$bin" compare "$results" "$work/portable" --out "$work/compare.html" || status=$?
# 0: nothing slower, 3: something slower (kernels may differ in speed); 1 or 2: broken.
if [[ "$status" -ne 0 && "$status" -ne 3 ]]; then
    echo "error: compare exited with $status" >&2
    exit 1
fi
check_page "$work/compare.html" compare
echo "browser checks passed"
