#!/usr/bin/env bash
# Regenerates the paper's Figures 8 and 12 (renderings of the tuning and cross brushed metal
# BRDFs) and Figure 18 (polar plots of measured Cornell paint data with fitted models) into
# results/fig08-render, results/fig12-render and results/fig18-polar.
#
# Each directory gets NOTE.generated.md (the figure's description with this run's renderer
# output, fitted RMSEs and commands), rewritten on every run, and a NOTE.md made from it only
# when there is none: NOTE.md is the hand-kept note (provenance, what changed, caveats), and
# a run never overwrites it. Compare the two after a run and carry over what changed.
#
# Run from anywhere (it changes to the repository root). The figures take a few seconds; the
# release build before them up to a couple of minutes when crates changed. Honours
# CARGO_TARGET_DIR.
set -euo pipefail

# --reuse-fits: redraw Figure 18 from the stored fits instead of fitting again (see below).
REUSE=0
if [[ "${1:-}" == "--reuse-fits" ]]; then
    REUSE=1
elif [[ -n "${1:-}" ]]; then
    echo "usage: $0 [--reuse-fits]" >&2
    exit 2
fi

cd "$(dirname "${BASH_SOURCE[0]}")/.."
cargo build --release -p harness
BIN="${CARGO_TARGET_DIR:-target}/release/brdf-sls"

# --- Figures 8 and 12 -------------------------------------------------------------------------
# One exposure for both so they compare directly: 1.6 brings the brightest point of the cross
# BRDF (kd plus both lobes) just below white without clipping; the tuning BRDF is then at about
# 60% of white at its streak.
EXPOSURE=1.6

# keep_note DIR: NOTE.md from NOTE.generated.md when DIR has no NOTE.md (never overwritten).
keep_note() {
    if [[ -e "$1/NOTE.md" ]]; then
        echo "kept $1/NOTE.md; this run's text is in $1/NOTE.generated.md"
    else
        cp "$1/NOTE.generated.md" "$1/NOTE.md"
    fi
}

render_figure() { # NUMBER PARAMS DESCRIPTION_OF_PAPER DESCRIPTION_OF_OURS
    local num=$1 params=$2 paper=$3 ours=$4
    local dir="results/fig${num}-render" png="results/fig${num}-render/fig${num}-${params}.png"
    mkdir -p "$dir"
    local cmd=("$BIN" render --params "$params" --exposure "$EXPOSURE" --out "$png")
    local out
    out=$("${cmd[@]}")
    echo "$out"
    cat >"$dir/NOTE.generated.md" <<NOTE
# Figure ${num#0}: the \`${params}\` BRDF rendered

**Paper.** ${paper}

**Ours.** ${ours}

Scene (the defaults of \`brdf-sls render\`, see \`brdf-sls render --help\`): a 3.2 x 3.2 square
in the z = 0 plane, the BRDF's x axis along the image's horizontal axis, a point light 1.9 above
its centre (intensity 3), a pinhole camera at (0, -0.6, 2.2) looking at the centre (66 degree
field of view), 512 x 512 pixels with 2 x 2 supersampling, clamp tone mapping, exposure
${EXPOSURE} (the same for Figures 8 and 12, so the two images compare directly). The light
sits close to the camera because the lobe (Cx = -1, Cy = 0.8, Cz = 0.96) reflects forward
along its x' axis but backward along y': near-retro-reflective geometry keeps the highlight
bright far out along y' and dark along x', which is what makes the anisotropy visible; a light
far to the side shows only a faint broad glow. The paper gives no scene parameters, so the
images match in kind, not pixel for pixel.

Renderer output: \`${out}\`

Command (from the repository root, after \`cargo build --release -p harness\`; the script
\`scripts/figures-render-polar.sh\` runs it):

\`\`\`
brdf-sls render --params ${params} --exposure ${EXPOSURE} --out ${png}
\`\`\`
NOTE
    keep_note "$dir"
}

render_figure 08 tuning \
    "Caption: \"A single point light source illuminating a flat surface with the tuning BRDF\", the BRDF of Table 2 (one anisotropic lobe, Cx = -1, Cy = 0.8, Cz = 0.96, n = 20, pan 45 degrees, kd = 0.15). Our copy of the paper is text only, so the image itself could not be compared; a single anisotropic lobe under a point light gives one elongated highlight." \
    "One bright diagonal streak through the centre, from upper left to lower right in the image: along the lobe's y' axis (pan + 90 = 135 degrees from the x axis), where the lobe is retro-reflective and stays bright, on the grey diffuse floor (kd = 0.15). Across the streak (along x', the pan direction) the highlight dies quickly."
render_figure 12 cross \
    "Caption: \"A single point light source illuminating a flat surface with a BRDF representing a cross brushed metal surface\", the BRDF of Table 3 (the Table 2 lobe at pan +45 degrees plus the same lobe at pan -45 degrees, kd = 0.15). Our copy of the paper is text only, so the image itself could not be compared; two such lobes give two crossed elongated highlights." \
    "An X: the streak of Figure 8 plus its mirror image from the lobe at pan -45 degrees (lower left to upper right), brightest at the centre where both lobes add to the diffuse term (just below white at this exposure)."


# --- Figure 18 --------------------------------------------------------------------------------
# The paper plotted the blue latex house paint at 550 nm (values > 1 dropped) at incident angles
# 0, 35 and 65 degrees; the Cornell files here are measured at 10, 20, ..., 80 degrees, so we
# use 10, 40 and 70. It overlaid its 1-lobe AED fit (Table 6) and Lafortune's own 3-lobe fit;
# we overlay our 1-lobe and 2-lobe AED fits of the same data. Targets sit just above the lowest
# RMSE that several 8-second AED runs (seeds 1-3) reached (the paper's way of choosing q), so
# each fit stops once it is as good as the search gets; the CPU budget is only a cap.
#
# Each fit's parameters go to results/fig18-polar/<data>-<k>lobe.json (and all of them, with
# how they were obtained, to fits.json); `--reuse-fits` redraws the plots from those files
# without fitting again (the solver may change; the stored fits are what the figures show).
#
# The fits use AED with the stall restart (stall_limit = 10, Figure 16's "AED stall"): the
# paper's AED can spend a whole run at a candidate with a dead lobe (sls::algorithms::aed docs).
# With git 77ae8bc, 2-lobe Krylon fits of 3 CPU s by the paper's AED stayed at the 1-lobe RMSE
# 0.026120 for seeds 1 and 8 of 1-8 (seed 8 also with the descents' singular-convergence test
# of the commit before); with the stall restart both reached the target in under 0.12 s.
SEED=1
CPU=5
STALL=10
INCIDENT=10,40,70
FIG18=results/fig18-polar
mkdir -p "$FIG18"

# fit_to_file DATA LOBES TARGET FILE: runs `brdf-sls fit`, writes the `json:` line to FILE and
# prints the RMSE (or, with --reuse-fits, evaluates the stored FILE).
fit_to_file() {
    local data=$1 lobes=$2 target=$3 file=$4 out rmse json
    if [[ $REUSE == 1 ]]; then
        [[ -s "$file" ]] || { echo "--reuse-fits: $file is missing; run without it" >&2; exit 1; }
        out=$("$BIN" eval "$data" --max-value 1 --params "$(cat "$file")")
        awk '/^RMSE /{print $2; exit}' <<<"$out"
        return
    fi
    out=$("$BIN" fit "$data" --max-value 1 --lobes "$lobes" --kind anisotropic --algorithm aed \
        --set stall_limit="$STALL" --seed "$SEED" --cpu-seconds "$CPU" --target "$target")
    rmse=$(awk '/^RMSE /{print $2; exit}' <<<"$out")
    json=$(sed -n 's/^json: //p' <<<"$out")
    if [[ -z "$rmse" || -z "$json" ]]; then
        echo "fit of $data ($lobes lobes) printed no RMSE/json line:" >&2
        echo "$out" >&2
        exit 1
    fi
    if ! grep -q '^target .* reached' <<<"$out"; then
        echo "note: $data ($lobes lobes) did not reach target $target in $CPU CPU s (RMSE $rmse)" >&2
    fi
    printf '%s\n' "$json" >"$file"
    echo "$rmse"
}

FITS_JSON="{"
NOTE_ROWS=""
NOTE_CMDS=""
sep=""
# name:1-lobe target:2-lobe target:radius. acryl_blue at 550 nm is nearly black apart from a
# mirror-like coat reflection that the value cap removes, so its panels are scaled to the
# measured (kept) values; fitted spikes beyond the rim show as gaps.
for entry in krylon_blue:0.02613:0.02394:auto acryl_blue:0.00131:0.000655:measured:1.5; do
    IFS=: read -r name t1 t2 radius <<<"$entry"
    data="experiments/data/${name}.brdf"
    f1="$FIG18/${name}-1lobe.json"
    f2="$FIG18/${name}-2lobe.json"
    r1=$(fit_to_file "$data" 1 "$t1" "$f1")
    r2=$(fit_to_file "$data" 2 "$t2" "$f2")
    base="$FIG18/fig18-${name}"
    polar=("$BIN" polar "$data" --max-value 1 --show-dropped --incident "$INCIDENT"
        --radius "$radius" --fit "1 lobe (AED)=@$f1" --fit "2 lobes (AED)=@$f2" --out "$base")
    "${polar[@]}"
    FITS_JSON+="${sep}
  \"${name}\": {
    \"data\": \"${data}\", \"wavelength_nm\": 550, \"max_value\": 1,
    \"algorithm\": \"aed\", \"stall_limit\": ${STALL}, \"seed\": ${SEED}, \"cpu_seconds\": ${CPU},
    \"fits\": [
      {\"label\": \"1 lobe (AED)\", \"lobes\": 1, \"kind\": \"anisotropic\", \"target\": ${t1}, \"rmse\": ${r1}, \"params\": $(cat "$f1")},
      {\"label\": \"2 lobes (AED)\", \"lobes\": 2, \"kind\": \"anisotropic\", \"target\": ${t2}, \"rmse\": ${r2}, \"params\": $(cat "$f2")}
    ]
  }"
    sep=","
    NOTE_ROWS+="| ${name} | ${r1} | ${r2} | fig18-${name}.png / .svg |
"
    NOTE_CMDS+="brdf-sls fit ${data} --max-value 1 --lobes 1 --kind anisotropic --algorithm aed --set stall_limit=${STALL} --seed ${SEED} --cpu-seconds ${CPU} --target ${t1} | sed -n 's/^json: //p' > ${f1}
brdf-sls fit ${data} --max-value 1 --lobes 2 --kind anisotropic --algorithm aed --set stall_limit=${STALL} --seed ${SEED} --cpu-seconds ${CPU} --target ${t2} | sed -n 's/^json: //p' > ${f2}
brdf-sls polar ${data} --max-value 1 --show-dropped --incident ${INCIDENT} --radius ${radius} --fit '1 lobe (AED)=@${f1}' --fit '2 lobes (AED)=@${f2}' --out ${base}
"
done
printf '%s\n}\n' "$FITS_JSON" >"$FIG18/fits.json"

cat >"$FIG18/NOTE.generated.md" <<NOTE
# Figure 18: measured paint BRDF and fitted Lafortune models in the plane of incidence

**Paper.** Polar plots of the blue latex house paint at 550 nm (Cornell data, values > 1
dropped) at incident angles 0, 35 and 65 degrees: the measured BRDF (blue), Lafortune's
3-lobe approximation (black) and the paper's 1-lobe AED fit of Table 6 (red, RMSE below 0.042).
The paper's text: Lafortune's approximation follows the measured curve better in the last two
slices although its RMSE is higher, and neither model captures the forward reflection at the
grazing 65 degrees.

**Ours.** The Cornell files here (\`experiments/data/*.brdf\`) are measured at incident angles
10, 20, ..., 80 degrees only, so the panels are at 10, 40 and 70 degrees. We do not compare
with a fit from another source: both curves are our own AED fits of the filtered data, a
1-lobe anisotropic fit (red) and a 2-lobe anisotropic fit (black). Blue dots are the kept
measurements in the plane (phi_s = 0 or 180 degrees; a thin line joins them in angle order);
hollow blue circles are measurements in the plane that the \`values > 1\` filter removed, on
the rim with their value printed when they lie beyond it. Radius is the BRDF value (linear),
angle the exitant direction from the normal, positive on the forward (mirror) side; the dashed
grey ray is the incident direction. Legend entries give each fit's RMSE on all kept samples.

| data (550 nm, values > 1 dropped) | RMSE 1 lobe | RMSE 2 lobes | files |
|---|---|---|---|
${NOTE_ROWS}
- **krylon_blue** (Krylon spray enamel; closest to the paper's data among the files we have):
  at 550 nm the paint is dark (diffuse about 0.008) with a glossy forward peak near the mirror
  direction. The 2-lobe fit follows the peak at 10 and 40 degrees closely; the 1-lobe fit is a
  compromise that badly underestimates the near-normal peak at 10 degrees, which is where most
  of the 2-lobe fit's RMSE gain comes from. At 70 degrees both fits rise toward the grazing
  forward direction where the filter removed the measured peak (values up to about 7.8, the
  hollow circles on the rim): like the paper's fits at 65 degrees, neither captures the real
  forward reflection, and here the data they were fitted to does not contain it. Unlike the
  paper (which found no gain from more than one lobe on its paint), the second lobe lowers the
  RMSE here.
- **acryl_blue** (acrylic paint): at 550 nm it is almost black (median value 0) except for a
  mirror-like reflection of 3 to 24 that the filter removes entirely, so the fits model the
  small remainder (RMSE about 0.001); the panels are scaled to the kept measurements
  (\`--radius measured:1.5\`), so fitted spikes toward the removed mirror peak leave the disc
  (gaps at the rim). This data set is a poor Figure 18 stand-in at 550 nm; it is shown because
  it is cheap and makes the effect of the filter plain.

Fits: AED with the stall restart (stall_limit = ${STALL}; the paper's AED can cycle at a dead
lobe), seed ${SEED}, at most ${CPU} CPU s, stopped at a target just above the lowest RMSE
several 8-second runs reached (the paper's way of choosing its threshold); the fitted
parameters are in \`<data>-<k>lobe.json\` and, with the settings, in \`fits.json\`. The AED
runs depend on the solver version, so later fits may differ slightly; \`scripts/figures-render-polar.sh
--reuse-fits\` redraws the figures from the stored parameters.

Commands (from the repository root; \`scripts/figures-render-polar.sh\` runs them):

\`\`\`
${NOTE_CMDS}\`\`\`
NOTE
keep_note "$FIG18"
echo "wrote results/fig08-render, results/fig12-render, $FIG18"
