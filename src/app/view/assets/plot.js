// The plot under the statistics of `masssprings view`: a panel or two over
// the last steps (the status's history, api.rs), each with its title and
// unit, tick labels on both axes, and a legend naming what each line is.
//
// * Alone: where each step stopped, its relative gradient ‖∇E‖ / ‖∇E₀‖
//   (line, log scale, no unit) and its iterations (bars, right axis); and
//   the time each step took (ms).
// * Comparing two solvers: both mechanical energies (kinetic, springs and
//   gravity: Simulation::mechanical_energy) above the lowest either
//   reached (J, log scale), which shows how fast each settles, whatever the
//   energy's size; and both times per step (ms).
// * Beside a program's own frames (--frames): the largest distance between
//   a vertex of ours and of the frames (m), and both energies.
//
// Nothing is plotted from nothing: with no steps yet, or an energy that
// never changed, the panel says so in words.
'use strict';

/** Blue: the first simulation; orange: the compared one (LOOK.second). */
const PLOT_COLOURS = ['#3f6fb0', '#d35400'];
const PLOT_INK = '#34495e';
const PLOT_GRID = 'rgba(93, 109, 126, 0.35)';

/** Superscript digits, for the powers of ten of a log axis. */
const SUPERSCRIPT = { '-': '⁻', 0: '⁰', 1: '¹', 2: '²', 3: '³', 4: '⁴', 5: '⁵', 6: '⁶', 7: '⁷', 8: '⁸', 9: '⁹' };

/** `10^k` written as 10⁻³ (1 and 10 as such). */
function powerOfTen(k) {
  if (k === 0) return '1';
  if (k === 1) return '10';
  return `10${String(k).split('').map((c) => SUPERSCRIPT[c]).join('')}`;
}

/** A number for a tick label: short, exact enough. */
function tickText(x) {
  if (x === 0) return '0';
  const size = Math.abs(x);
  if (size >= 1e4 || size < 1e-2) return x.toExponential(0).replace('e+', 'e');
  return String(Number(x.toPrecision(3)));
}

/** Tick values from 0 (or `low`) up to `high`: 1, 2 or 5 × 10^k apart,
 *  at most `count` + 1 of them. */
function niceTicks(low, high, count = 4) {
  const span = Math.max(high - low, 1e-300);
  const raw = span / count;
  const power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * power).find((m) => m >= raw);
  const ticks = [];
  for (let t = Math.ceil(low / step) * step; t <= high + 1e-9 * step; t += step) ticks.push(Number(t.toPrecision(12)));
  return ticks;
}

/** The compared simulation's history, aligned with the first's by step
 *  (the two step together; the comparison may have started later). */
function alignedHistory(s) {
  const byStep = new Map(s.compare.history.map((record) => [record.step, record]));
  return s.history.map((record) => byStep.get(record.step) || null);
}

/** [step, value] of each record whose `value` is a finite number. */
function points(history, value) {
  return history.flatMap((record) => {
    if (!record) return [];
    const v = value(record);
    return v === null || v === undefined || !Number.isFinite(v) ? [] : [[record.step, v]];
  });
}

const NO_STEPS = 'no steps yet: step (space) or ▶ play (A)';

/** What to plot for status `s`; `names` are the two simulations' names. */
function plotPanels(s, names) {
  if (!s.compare) return [convergencePanel(s), timePanel(s, null, names)];
  const second = alignedHistory(s);
  if (s.compare.solver === 'frames') return [distancePanel(s, second), energyPanel(s, second, names)];
  return [energyPanel(s, second, names), timePanel(s, second, names)];
}

function convergencePanel(s) {
  const gradient = points(s.history, (r) => r.relative_gradient);
  const iterations = points(s.history, (r) => r.iterations);
  const measured = gradient.length > 0 || s.history.length === 0;
  return {
    title: measured
      ? 'each step: relative gradient (line, log), iterations (bars)'
      : 'iterations of each step (relative gradient not measured)',
    hover: 'For each of the last steps: how far from the minimum it stopped, ‖∇E(p)‖ over ‖∇E(pᵗ)‖ on the free '
      + 'vertices (no unit; 1: no closer by this measure), and the iterations it used, up to its budget.',
    scale: 'log',
    series: [
      { name: 'relative gradient', colour: PLOT_COLOURS[0], points: gradient },
      { name: `iterations (right axis, of ${s.iterations})`, colour: 'rgba(127, 140, 141, 0.55)', points: iterations,
        bars: true, right: { max: Math.max(1, s.iterations, ...iterations.map((p) => p[1])), unit: 'iterations' } },
    ],
    empty: s.history.length === 0 ? NO_STEPS : null,
  };
}

function timePanel(s, second, names) {
  const series = [{ name: names[0], colour: PLOT_COLOURS[0], points: points(s.history, (r) => r.ms) }];
  if (second) series.push({ name: names[1], colour: PLOT_COLOURS[1], points: points(second, (r) => r.ms) });
  return {
    title: 'time per step (ms)',
    hover: 'Milliseconds each of the last steps took, measured around Simulation::step on the server.',
    scale: 'linear',
    series,
    empty: s.history.length === 0 ? NO_STEPS : null,
  };
}

function energyPanel(s, second, names) {
  const all = [...s.history, ...second.filter(Boolean)].map((r) => r.energy).filter(Number.isFinite);
  const lowest = Math.min(...all);
  const spread = Math.max(...all) - lowest;
  const floor = lowest - 1e-4 * spread;
  const above = (r) => r.energy - floor;
  let empty = null;
  if (all.length === 0) {
    empty = NO_STEPS;
  } else if (!(spread > 1e-12 * Math.max(1, Math.abs(lowest)))) {
    empty = `mechanical energy ${tickText(lowest)} J at every step: nothing moves (at rest)`;
  }
  return {
    title: 'energy above the lowest reached (J, log)',
    hover: 'Kinetic energy, the springs\' and gravity\'s (Simulation::mechanical_energy) after each step, minus the '
      + `lowest either reached (${tickText(lowest)} J): the faster a line falls, the faster that simulation settles.`,
    scale: 'log',
    series: [
      { name: names[0], colour: PLOT_COLOURS[0], points: points(s.history, above) },
      { name: names[1], colour: PLOT_COLOURS[1], points: points(second, above) },
    ],
    empty,
  };
}

function distancePanel(s, second) {
  const distances = points(second, (r) => r.distance);
  const largest = Math.max(0, ...distances.map((p) => p[1]));
  let title = 'distance to your frames (m, the largest over vertices)';
  if (distances.length > 0 && largest === 0) title = 'distance to your frames: 0 m at every step, the same';
  let empty = s.history.length === 0 ? NO_STEPS : null;
  if (!empty && distances.length === 0) empty = `your frames end at step ${s.frames ? s.frames.steps : '?'}`;
  return {
    title,
    hover: 'After each step, the largest distance between a vertex of this simulation and the same vertex of your '
      + 'frame of that step, in the scene\'s unit of length (m).',
    scale: 'linear',
    series: [{ name: 'ours − your frames', colour: PLOT_COLOURS[1], points: distances }],
    empty,
  };
}

/** Draws `panels` on `canvas` at `font` CSS pixels; returns every text
 *  drawn (for the browser tests). */
function drawPlot(canvas, panels, font) {
  const ratio = window.devicePixelRatio || 1;
  const width = Math.max(200, canvas.clientWidth);
  const panelHeight = Math.round(10.4 * font);
  const height = panels.length * panelHeight;
  if (canvas.style.height !== `${height}px`) canvas.style.height = `${height}px`;
  const [w, h] = [Math.round(width * ratio), Math.round(height * ratio)];
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w;
    canvas.height = h;
  }
  const c = canvas.getContext('2d');
  c.setTransform(ratio, 0, 0, ratio, 0, 0);
  c.clearRect(0, 0, width, height);
  const texts = [];
  panels.forEach((panel, i) => {
    drawPanel(c, panel, { top: i * panelHeight, width, height: panelHeight }, font, texts);
  });
  return texts;
}

/** One panel in the band `box` of the canvas. */
function drawPanel(c, panel, box, font, texts) {
  const write = (text, x, y, align = 'left', colour = PLOT_INK) => {
    c.fillStyle = colour;
    c.textAlign = align;
    c.fillText(text, x, y);
    texts.push(text);
  };
  c.font = `600 ${font}px system-ui, sans-serif`;
  write(fitText(c, panel.title, box.width), 0, box.top + font);
  c.font = `${font}px system-ui, sans-serif`;
  const area = { top: box.top + 1.6 * font, bottom: box.top + box.height - 3.3 * font };
  if (panel.empty) {
    write(fitText(c, panel.empty, box.width), box.width / 2, (area.top + area.bottom) / 2 + font / 3, 'center', '#7f8c8d');
    return;
  }
  const plotted = panel.series.filter((serie) => !serie.right);
  const yAxis = valueAxis(plotted.flatMap((serie) => serie.points.map((p) => p[1])), panel.scale);
  const right = panel.series.find((serie) => serie.right);
  const rightTicks = right ? niceTicks(0, right.right.max, 2) : [];
  if (plotted.every((serie) => serie.points.length === 0)) yAxis.ticks = [];
  const yWidth = Math.max(0, ...yAxis.ticks.map((t) => c.measureText(t.text).width));
  area.left = yWidth + 0.6 * font;
  area.right = box.width - (right ? Math.max(...rightTicks.map((t) => c.measureText(tickText(t)).width)) + 0.6 * font : 0.5 * font);
  const steps = panel.series.flatMap((serie) => serie.points.map((p) => p[0]));
  const [first, last] = [Math.min(...steps), Math.max(...steps)];
  const xOf = (step) => area.left + (area.right - area.left) * (last > first ? (step - first) / (last - first) : 0.5);
  const yOf = (value) => area.bottom + (area.top - area.bottom) * (yAxis.map(value) - yAxis.low) / (yAxis.high - yAxis.low || 1);
  // Grid and tick labels.
  for (const tick of yAxis.ticks) {
    const y = yOf(tick.value);
    c.fillStyle = PLOT_GRID;
    c.fillRect(area.left, y, area.right - area.left, 1);
    write(tick.text, area.left - 0.3 * font, y + font / 3, 'right');
  }
  if (right) {
    for (const t of rightTicks) {
      const y = area.bottom + (area.top - area.bottom) * t / right.right.max;
      write(tickText(t), area.right + 0.3 * font, y + font / 3, 'left', '#7f8c8d');
    }
  }
  // The steps along the bottom, the axis's name under the value axis.
  const row = area.bottom + 1.4 * font;
  const name = c.measureText('step').width;
  for (const step of stepTicks(first, last)) {
    const [x, half] = [xOf(step), c.measureText(String(step)).width / 2];
    if (x - half <= name + 0.5 * font) continue;
    if (x + half > box.width) write(String(step), box.width, row, 'right'); // the last, inside the canvas
    else write(String(step), x, row, 'center');
  }
  write('step', 0, row);
  // The series: bars first, then lines.
  const columnWidth = Math.max(1.5, (area.right - area.left) / Math.max(1, last - first + 1) - 1);
  for (const serie of panel.series.filter((s) => s.bars)) {
    c.fillStyle = serie.colour;
    for (const [step, value] of serie.points) {
      const top = area.bottom + (area.top - area.bottom) * value / serie.right.max;
      c.fillRect(xOf(step) - columnWidth / 2, top, columnWidth, area.bottom - top);
    }
  }
  c.save();
  c.beginPath();
  c.rect(area.left, area.top, area.right - area.left, area.bottom - area.top);
  c.clip(); // nothing drawn over the title, the ticks or the legend
  for (const serie of panel.series.filter((s) => !s.bars)) {
    c.strokeStyle = serie.colour;
    c.fillStyle = serie.colour;
    c.lineWidth = Math.max(2, font / 7);
    c.beginPath();
    serie.points.forEach(([step, value], i) => {
      if (i === 0) c.moveTo(xOf(step), yOf(value)); else c.lineTo(xOf(step), yOf(value));
    });
    c.stroke();
    if (serie.points.length === 1) {
      const [step, value] = serie.points[0];
      c.fillRect(xOf(step) - 3, yOf(value) - 3, 6, 6);
    }
  }
  c.restore();
  drawLegend(c, panel.series, { left: 0, top: box.top + box.height - 0.6 * font, width: box.width }, font, write);
}

/** The value axis of `values` on `scale`: the map to plotted units, its
 *  range and its tick labels. */
function valueAxis(values, scale) {
  if (scale === 'log') {
    const positive = values.filter((v) => v > 0);
    const logs = positive.length ? positive.map(Math.log10) : [0];
    let low = Math.floor(Math.min(...logs));
    let high = Math.ceil(Math.max(...logs));
    if (high === low) high = low + 1;
    const every = Math.max(1, Math.ceil((high - low) / 4));
    low = Math.floor(low / every) * every;
    high = Math.ceil(high / every) * every;
    const ticks = [];
    for (let k = low; k <= high; k += every) ticks.push({ value: 10 ** k, text: powerOfTen(k) });
    return { map: (v) => Math.log10(Math.max(v, 10 ** (low - 1))), low, high, ticks };
  }
  const high = Math.max(...values, 0);
  const ticks = niceTicks(0, high > 0 ? high : 1, 3);
  // one tick more when the largest value lies above the last one
  const last = ticks[ticks.length - 1];
  if (ticks.length > 1 && last < high) ticks.push(Number((2 * last - ticks[ticks.length - 2]).toPrecision(12)));
  const top = ticks[ticks.length - 1];
  return { map: (v) => v, low: 0, high: top, ticks: ticks.map((t) => ({ value: t, text: tickText(t) })) };
}

/** Whole steps to label between `first` and `last`: at most five. */
function stepTicks(first, last) {
  if (!Number.isFinite(first)) return [];
  if (last === first) return [first];
  return niceTicks(first, last, 4).filter((t) => Number.isInteger(t) && t >= first && t <= last);
}

/** A swatch and the name of each series, in a row, shortened to fit. */
function drawLegend(c, series, { left, top, width }, font, write) {
  let x = left;
  const room = width / series.length;
  for (const serie of series) {
    c.fillStyle = serie.colour;
    c.fillRect(x, top - 0.7 * font, 0.9 * font, serie.bars ? 0.7 * font : 0.25 * font);
    write(fitText(c, serie.name, room - 1.6 * font), x + 1.2 * font, top);
    x += room;
  }
}

/** `text`, cut with an ellipsis to fit `width` pixels in the current font. */
function fitText(c, text, width) {
  if (c.measureText(text).width <= width) return text;
  let cut = text;
  while (cut.length > 1 && c.measureText(`${cut}…`).width > width) cut = cut.slice(0, -1);
  return `${cut}…`;
}
