// Time charts with uPlot (served from vendor/, installed from npm): one x axis of time, a few
// series, zoom by dragging across the chart (the caller fetches the narrower range again, so the
// historian aggregates it into finer intervals) and back to the chosen range by double-click.
import uPlot from '../vendor/uPlot.esm.js';

const COLOURS = ['#1f6feb', '#1a7f37', '#b7791f', '#cf222e', '#8250df', '#57606a'];

function width(container) {
  return Math.max(280, container.clientWidth || container.parentElement.clientWidth || 600);
}

// series: [{label, fill?, dash?, scale?}]; onZoom(fromMs, toMs) and onReset() when given.
export function timeChart(container, series, {onZoom, onReset, height = 220, percent = false} = {}) {
  const options = {
    width: width(container),
    height,
    cursor: {drag: {x: true, y: false, setScale: !onZoom}},
    scales: percent ? {y: {range: [0, 1]}} : {},
    axes: [{}, percent ? {values: (u, ticks) => ticks.map((v) => `${Math.round(v * 100)} %`)} : {}],
    series: [{}, ...series.map((s, i) => ({
      label: s.label,
      stroke: s.stroke || COLOURS[i % COLOURS.length],
      fill: s.fill,
      dash: s.dash,
      width: s.width || 1.5,
      spanGaps: false,
      points: {show: false},
    }))],
    hooks: {
      setSelect: [(u) => {
        // Nothing drawn, nothing to zoom into (the x scale of an empty chart is no time range).
        if (!onZoom || u.select.width < 2 || u.data[0].length < 2) return;
        const from = u.posToVal(u.select.left, 'x') * 1000;
        const to = u.posToVal(u.select.left + u.select.width, 'x') * 1000;
        u.setSelect({left: 0, top: 0, width: 0, height: 0}, false);
        onZoom(from, to);
      }],
    },
  };
  const empty = [[], ...series.map(() => [])];
  const plot = new uPlot(options, empty, container);
  if (onReset) plot.over.addEventListener('dblclick', () => onReset());
  new ResizeObserver(() => plot.setSize({width: width(container), height})).observe(container);
  return {
    plot,
    // times in ms, columns one array per series (null for a gap).
    setData(times, columns) {
      plot.setData([times.map((t) => t / 1000), ...columns]);
    },
  };
}
