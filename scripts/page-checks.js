// Layout checks of a brdf-sls page, run by scripts/ci-browser.sh in headless Chromium on a
// copy of the page with this script appended (the pages themselves carry no script). Each
// failure is a line "FAIL: ..." in <pre id="page-checks">, which --dump-dom prints; the
// shell script greps for them.
//
// Checks:
// - the page is no wider than the window (no horizontal scrolling; tables too wide scroll in
//   their own box);
// - on a report page, the summary table starts within the first screen;
// - no chart's legend overlaps its plotting area, and no text is drawn inside it;
// - a configuration keeps one colour across the figures of the page;
// - no number cell holds a number with more than 8 significant digits.
(function () {
  const fails = [];
  const notes = [];
  const fail = (m) => fails.push("FAIL: " + m);
  const vw = window.innerWidth;
  const vh = window.innerHeight;

  const width = document.documentElement.scrollWidth;
  if (width > vw) {
    fail(`the page is ${width} px wide in a window ${vw} px wide`);
  }

  const summary = document.querySelector("table.summary");
  if (document.title.startsWith("brdf-sls report")) {
    if (!summary) {
      fail("a report page without a summary table");
    } else {
      const top = summary.getBoundingClientRect().top + window.scrollY;
      if (top >= vh) {
        fail(`the summary table starts at ${Math.round(top)} px, below the first screen (${vh} px)`);
      }
      notes.push(`summary at ${Math.round(top)} px of ${vh}`);
    }
  }

  const overlap = (a, b) =>
    a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
  const colours = new Map();
  let figures = 0;
  for (const fig of document.querySelectorAll("figure.chart")) {
    figures += 1;
    const svg = fig.querySelector("svg[data-plot-area]");
    if (!svg) {
      fail(`figure ${fig.id}: no chart with a plotting area`);
      continue;
    }
    const [l, t, r, b] = svg.dataset.plotArea.split(" ").map(Number);
    const box = svg.getBoundingClientRect();
    const scale = box.width / Number(svg.getAttribute("width"));
    const plot = {
      left: box.left + l * scale,
      top: box.top + t * scale,
      right: box.left + r * scale,
      bottom: box.top + b * scale,
    };
    const legend = fig.querySelector("ul.legend");
    if (legend && overlap(legend.getBoundingClientRect(), plot)) {
      fail(`figure ${fig.id}: its legend overlaps the plotting area`);
    }
    for (const text of svg.querySelectorAll("text")) {
      const tb = text.getBoundingClientRect();
      const inside = tb.left > plot.left + 1 && tb.right < plot.right - 1 &&
        tb.top > plot.top + 1 && tb.bottom < plot.bottom - 1;
      if (inside && text.textContent.trim()) {
        fail(`figure ${fig.id}: text "${text.textContent.trim()}" drawn inside the plotting area`);
      }
    }
    for (const li of fig.querySelectorAll("ul.legend li[data-key]")) {
      const mark = li.querySelector("svg.swatch line, svg.swatch circle, svg.swatch rect");
      if (!mark) continue;
      const c = mark.getAttribute("stroke") || mark.getAttribute("fill");
      const key = li.dataset.key;
      const seen = colours.get(key);
      if (seen && seen.colour !== c) {
        fail(`"${key}" is ${seen.colour} in figure ${seen.figure} but ${c} in figure ${fig.id}`);
      } else if (!seen) {
        colours.set(key, { colour: c, figure: fig.id });
      }
    }
  }

  let cells = 0;
  for (const td of document.querySelectorAll("td.num")) {
    cells += 1;
    for (const n of td.textContent.match(/\d[\d.]*(?:e[-+]?\d+)?/gi) || []) {
      const mantissa = n.split(/e/i)[0].replace(".", "").replace(/^0+/, "");
      if (mantissa.length > 8) {
        fail(`a number cell holds ${n} (${mantissa.length} significant digits): "${td.textContent.trim()}"`);
        break;
      }
    }
  }

  const pre = document.createElement("pre");
  pre.id = "page-checks";
  pre.textContent = [
    `checked: ${figures} figures, ${colours.size} configuration colours, ${cells} number cells, ` +
      `${width} px wide at ${vw} px; ${notes.join("; ")}`,
    ...fails,
  ].join("\n");
  document.body.appendChild(pre);
})();
