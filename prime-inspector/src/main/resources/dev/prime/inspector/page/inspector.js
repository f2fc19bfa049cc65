// The inspector's page: draws the layout the server computed (/api/topology) as SVG, then
// follows the server-sent events of /api/events[/NAME]: "figures" update every box, "values"
// extend the plot of the chosen name. No library: the page must work with no internet.
'use strict';
(function () {
  const SVG = 'http://www.w3.org/2000/svg';
  const WINDOW_MS = 60000; // the plot shows the last minute of recorded time
  // Per field, points older than the window are dropped; the stream sends at most 300 values an
  // event, two events a second, so a minute is at most 36000 of them (the cap bounds memory only).
  const MAX_POINTS = 36000;
  const MAX_DRAWN = 2400; // per line: more are thinned out evenly, the latest always drawn
  const MAX_FIELDS = 6; // drawn; the rest are named in the legend
  const COUNTER = /(^|\.)(step|seq|sequence|count|counter|tick)$/i; // start hidden
  const COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#17becf'];
  const SOURCES = ['EventSource', 'ForeignSource', 'SourceLink', 'Filter', 'FlatMap', 'Combinator', 'Timer'];
  const TEMPLATES = ['IfElse', 'ForEach', 'Union', 'Fork', 'Guard', 'IsolatedUser', 'SyncCollector',
    'AsyncCollector', 'Repeater'];

  const state = {
    topology: null,
    boxes: new Map(), // name -> <g>
    plotted: null,
    series: new Map(), // field -> [[t, v], ...]
    hidden: new Set(), // fields not drawn (click a legend item to switch)
    latest: 0,
    events: null,
    nodeCount: -1,
    elsewhere: '', // the services another process hosts, as the topology gave them (JSON)
    loading: false,
  };

  const $ = (id) => document.getElementById(id);

  function svg(name, attrs, parent) {
    const e = document.createElementNS(SVG, name);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    if (parent) parent.appendChild(e);
    return e;
  }

  function problem(text) {
    const p = $('problem');
    p.textContent = text || '';
    p.hidden = !text;
  }

  async function loadTopology() {
    state.loading = true;
    try {
      const answer = await fetch('/api/topology', { cache: 'no-store' });
      if (!answer.ok) throw new Error(await answer.text());
      state.topology = await answer.json();
      state.nodeCount = state.topology.nodeCount;
      state.elsewhere = JSON.stringify(state.topology.hostedElsewhere);
      drawDiagram();
      fillChoice();
    } catch (e) {
      problem('Cannot read the topology: ' + e.message);
    } finally {
      state.loading = false;
    }
  }

  // ------------------------------------------------------------------ diagram

  function shape(kind, w, h, g) {
    const c = { class: 'shape' };
    const s = 10;
    if (kind === 'BlockChain') return svg('rect', { ...c, width: w, height: h, rx: 4 }, g);
    if (kind === 'EventSource' || kind === 'Timer') return svg('rect', { ...c, width: w, height: h, rx: h / 2 }, g);
    if (kind === 'ReaderNode') return svg('ellipse', { ...c, cx: w / 2, cy: h / 2, rx: w / 2, ry: h / 2 }, g);
    if (kind === 'ForeignChain') return svg('polygon', { ...c, points: `${s},0 ${w},0 ${w - s},${h} 0,${h}` }, g);
    if (kind === 'ForeignSource') return svg('polygon', { ...c, points: `0,0 ${w},0 ${w - s},${h} ${s},${h}` }, g);
    if (kind === 'Listener') return svg('polygon', { ...c, points: `0,0 ${w},0 ${w},${h} 0,${h} ${s},${h / 2}` }, g);
    if (kind === 'SourceLink' || kind === 'Filter' || kind === 'FlatMap' || kind === 'Combinator') {
      const r = 6;
      const body = svg('path', { ...c, d: `M0,${r} A${w / 2},${r} 0 0,1 ${w},${r} V${h - r} A${w / 2},${r} 0 0,1 0,${h - r} Z` }, g);
      svg('path', { class: 'shape', d: `M0,${r} A${w / 2},${r} 0 0,0 ${w},${r}`, fill: 'none' }, g);
      return body;
    }
    if (kind === 'GenericServiceNode') {
      const body = svg('rect', { ...c, width: w, height: h }, g);
      svg('line', { class: 'shape', x1: 7, y1: 0, x2: 7, y2: h }, g);
      svg('line', { class: 'shape', x1: w - 7, y1: 0, x2: w - 7, y2: h }, g);
      return body;
    }
    // templates and collectors: a hexagon
    return svg('polygon', { ...c, points: `${s},0 ${w - s},0 ${w},${h / 2} ${w - s},${h} ${s},${h} 0,${h / 2}` }, g);
  }

  function shortLabel(label, width) {
    const fits = Math.max(6, Math.floor((width - 16) / 7));
    return label.length <= fits ? label : label.slice(0, fits - 1) + '…';
  }

  function drawDiagram() {
    const t = state.topology;
    const root = $('diagram');
    root.replaceChildren();
    root.setAttribute('viewBox', `0 0 ${t.width} ${t.height + 30}`);
    root.style.maxWidth = Math.max(t.width, 480) + 'px';
    const defs = svg('defs', {}, root);
    const marker = svg('marker', { id: 'arrow', viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 7, markerHeight: 7, orient: 'auto-start-reverse' }, defs);
    svg('path', { d: 'M0,0 L10,5 L0,10 z', fill: '#59627a' }, marker);
    const byId = new Map(t.nodes.map((n) => [n.id, n]));
    const edges = svg('g', { class: 'edges' }, root);
    for (const e of t.edges) {
      const a = byId.get(e.from);
      const b = byId.get(e.to);
      let d;
      let mid;
      if (b.layer > a.layer) {
        const x1 = a.x + a.width, y1 = a.y + a.height / 2, x2 = b.x - 2, y2 = b.y + b.height / 2;
        const dx = Math.max(30, (x2 - x1) / 2);
        d = `M${x1},${y1} C${x1 + dx},${y1} ${x2 - dx},${y2} ${x2},${y2}`;
        mid = [(x1 + x2) / 2, (y1 + y2) / 2 - 4];
      } else {
        // the same or an earlier column: a loop under both boxes
        const x1 = a.x + a.width / 2, y1 = a.y + a.height, x2 = b.x + b.width / 2, y2 = b.y + b.height + 2;
        const low = Math.max(y1, y2) + 26;
        d = `M${x1},${y1} C${x1},${low} ${x2},${low} ${x2},${y2}`;
        mid = [(x1 + x2) / 2, low - 2];
      }
      svg('path', { class: e.role ? 'edge runs' : 'edge', d, 'marker-end': 'url(#arrow)' }, edges);
      if (e.role) {
        const label = svg('text', { class: 'edge-label', x: mid[0], y: mid[1] }, edges);
        label.textContent = e.role;
      }
    }
    state.boxes.clear();
    const recorded = new Set(t.recorded);
    const nodes = svg('g', { class: 'nodes' }, root);
    for (const n of t.nodes) {
      const kinds = ['node'];
      if (SOURCES.includes(n.kind)) kinds.push('source');
      if (TEMPLATES.includes(n.kind)) kinds.push('template');
      if (n.kind === 'ReaderNode') kinds.push('reader');
      if (n.elsewhere) kinds.push('elsewhere');
      if (n.service) kinds.push('service');
      if (recorded.has(n.name)) kinds.push('recorded');
      if (n.name === state.plotted) kinds.push('plotted');
      const g = svg('g', { class: kinds.join(' '), transform: `translate(${n.x},${n.y})`, 'data-name': n.name, 'data-kind': n.kind }, nodes);
      svg('title', {}, g).textContent = `${n.label} — ${n.kind}${n.service ? ', a service' : ''}${n.elsewhere ? ', hosted by another process' : ''}`;
      shape(n.kind, n.width, n.height, g);
      const label = svg('text', { class: 'label', x: n.width / 2, y: 21 }, g);
      label.textContent = shortLabel(n.label, n.width);
      const figures = svg('text', { class: 'figures', x: n.width / 2, y: 39 }, g);
      figures.textContent = n.elsewhere ? 'hosted elsewhere' : '–';
      if (recorded.has(n.name)) g.addEventListener('click', () => choose(n.name));
      state.boxes.set(n.name, g);
    }
    const elsewhere = t.nodes.filter((n) => n.elsewhere).length;
    $('core').textContent = `core '${t.core}' on ${t.media}`
      + (elsewhere ? ` · ${elsewhere} of ${t.services.length} services hosted by other processes (dashed)` : '');
    $('figures-note').textContent = t.figures;
    $('recording-off').hidden = t.recording;
  }

  function fmt(x) {
    if (x === null || x === undefined || Number.isNaN(x)) return '–';
    const a = Math.abs(x);
    if (a !== 0 && (a < 0.01 || a >= 1e6)) return x.toExponential(2);
    return a >= 100 ? x.toFixed(0) : a >= 10 ? x.toFixed(1) : x.toFixed(2);
  }

  function duration(ms) {
    if (ms >= 1) return `${fmt(ms)} ms`;
    if (ms >= 0.001) return `${fmt(ms * 1000)} µs`;
    return `${fmt(ms * 1e6)} ns`;
  }

  function onFigures(f) {
    if (f.error) problem(f.error); else problem('');
    const running = f.closed ? 'closed' : f.started ? 'running' : 'not started';
    $('state').textContent = `${running} · updated ${new Date(f.time).toLocaleTimeString()}`;
    $('state').classList.remove('down');
    const redraw = (f.nodeCount !== undefined && f.nodeCount !== state.nodeCount)
      || (f.hostedElsewhere !== undefined && JSON.stringify(f.hostedElsewhere) !== state.elsewhere);
    if (redraw && !state.loading) {
      loadTopology(); // declarations were added, or another process took a service or gave one up
      return;
    }
    for (const [name, g] of state.boxes) {
      const n = f.nodes[name];
      if (!n) continue;
      const parts = [`${n.rate.toFixed(1)}/s`];
      if (n.latencyMs !== null) parts.push(duration(n.latencyMs));
      if (n.errors !== null) parts.push(`${n.errors} err`);
      if (n.latencyMs === null && n.errors === null) parts.push(`${n.total} in all`);
      if (n.deadLetters > 0) parts.push(`${n.deadLetters} dead`);
      if (n.queueDepth > 0) parts.push(`${n.queueDepth} queued`);
      if (n.queueUnknown) parts.push('queue ?');
      if (n.missed > 0) parts.push(`${n.missed} missed`);
      g.querySelector('.figures').textContent = parts.join(' · ');
      g.setAttribute('data-rate', String(n.rate));
      g.setAttribute('data-total', String(n.total));
      for (const key of ['latencyMs', 'errors', 'deadLetters', 'queueDepth', 'missed']) {
        if (n[key] !== null) g.setAttribute('data-' + key.toLowerCase(), String(n[key]));
        else g.removeAttribute('data-' + key.toLowerCase());
      }
      g.classList.toggle('queue-unknown', n.queueUnknown === true);
      const title = g.querySelector('title');
      title.textContent = title.textContent.split('\n')[0]
        + `\n${n.total} values in all` + (n.errors !== null ? `, ${n.errors} failed` : '')
        + (n.deadLetters !== null ? `, ${n.deadLetters} dead letters` : '')
        + (n.queueDepth !== null && n.queueDepth >= 0 ? `, ${n.queueDepth} queued` : '')
        + (n.queueUnknown ? ', queue depth unknown (the media cannot read it now)' : '')
        + (n.missed !== null ? `, ${n.missed} missed` : '');
      g.classList.toggle('active', n.rate > 0);
      g.classList.toggle('failing', n.errors > 0);
    }
  }

  // ------------------------------------------------------------------ plot

  function fillChoice() {
    const select = $('plot-choice');
    const t = state.topology;
    select.replaceChildren();
    select.disabled = !t.recording || t.recorded.length === 0;
    if (select.disabled) {
      select.appendChild(new Option(t.recording ? 'nothing recorded yet' : 'recording is off', ''));
      connect(null);
      return;
    }
    for (const name of t.recorded) select.appendChild(new Option(name, name));
    const wanted = new URLSearchParams(location.hash.slice(1)).get('plot');
    const name = wanted !== null ? wanted : state.plotted !== null && t.recorded.includes(state.plotted) ? state.plotted : t.recorded[0];
    choose(name);
  }

  async function choose(name) {
    $('plot-choice').value = name;
    if (name === state.plotted && state.events) return;
    state.plotted = name;
    state.series = new Map();
    state.hidden = new Set();
    state.latest = 0;
    for (const [n, g] of state.boxes) g.classList.toggle('plotted', n === name);
    history.replaceState(null, '', '#plot=' + encodeURIComponent(name));
    $('plot-status').textContent = '';
    const check = await fetch('/api/values/' + encodeURIComponent(name), { cache: 'no-store' });
    if (!check.ok) {
      $('plot-status').textContent = await check.text();
      state.plotted = null;
      connect(null);
      drawPlot();
      return;
    }
    connect(name);
    drawPlot();
  }

  function onValues(v) {
    if (v.service !== state.plotted) return;
    for (const p of v.points) {
      state.latest = Math.max(state.latest, p.t);
      for (const [field, value] of Object.entries(p.fields)) {
        let s = state.series.get(field);
        if (!s) {
          state.series.set(field, (s = []));
          if (COUNTER.test(field)) state.hidden.add(field); // a counter would flatten the rest
        }
        if (value === null) continue; // NaN or an infinity, which JSON has not: left out, not drawn as 0
        s.push([p.t, value]);
      }
    }
    for (const s of state.series.values()) {
      let old = 0; // the points before the last minute of recorded time, and beyond the cap
      while (old < s.length && s[old][0] < state.latest - WINDOW_MS) old++;
      old = Math.max(old, s.length - MAX_POINTS);
      if (old > 0) s.splice(0, old);
    }
    const dropped = v.dropped > 0 ? ` (${v.dropped} older values fell out of the recording's ring)` : '';
    $('plot-status').textContent = state.series.size === 0
      ? `the values of ${v.service} have no numbers to plot (numbers, booleans and records' numeric components are plotted)`
      : `last value #${v.points.length ? v.points[v.points.length - 1].seq : '?'}${dropped}`;
    drawPlot();
  }

  function drawPlot() {
    const root = $('plot');
    const width = Math.max(320, Math.round(root.getBoundingClientRect().width) || 960);
    const height = 280;
    root.setAttribute('viewBox', `0 0 ${width} ${height}`);
    root.replaceChildren();
    const legend = $('legend');
    legend.replaceChildren();
    const left = 64, right = 12, top = 12, bottom = 26;
    const fields = [...state.series.keys()];
    let first = state.latest;
    for (const f of fields) { const s0 = state.series.get(f); if (s0.length) first = Math.min(first, s0[0][0]); }
    const span = Math.max(5000, Math.min(WINDOW_MS, state.latest - first)); // the last minute at most
    const x0 = state.latest - span;
    const drawn = fields.slice(0, MAX_FIELDS);
    let lo = Infinity, hi = -Infinity;
    const shown = drawn.filter((f) => !state.hidden.has(f));
    for (const f of shown) for (const [t, v] of state.series.get(f)) if (t >= x0) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (!Number.isFinite(lo)) { lo = 0; hi = 1; }
    if (hi === lo) { hi += 0.5; lo -= 0.5; }
    const pad = (hi - lo) * 0.06;
    lo -= pad; hi += pad;
    const X = (t) => left + ((t - x0) / span) * (width - left - right);
    const Y = (v) => top + (1 - (v - lo) / (hi - lo)) * (height - top - bottom);
    for (let i = 0; i <= 4; i++) {
      const v = lo + ((hi - lo) * i) / 4;
      svg('line', { class: 'grid', x1: left, x2: width - right, y1: Y(v), y2: Y(v) }, root);
      svg('text', { class: 'tick', x: left - 6, y: Y(v) + 4, 'text-anchor': 'end' }, root).textContent = fmt(v);
    }
    for (let i = 0; i <= 4; i++) {
      const t = x0 + (span * i) / 4;
      const anchor = i === 0 ? 'start' : i === 4 ? 'end' : 'middle';
      svg('text', { class: 'tick', x: X(t), y: height - 8, 'text-anchor': anchor }, root).textContent =
        i === 4 ? 'latest' : `-${((span * (4 - i)) / 4 / 1000).toFixed(1)} s`;
    }
    svg('line', { class: 'axis', x1: left, x2: left, y1: top, y2: height - bottom }, root);
    svg('line', { class: 'axis', x1: left, x2: width - right, y1: height - bottom, y2: height - bottom }, root);
    drawn.forEach((f, i) => {
      if (!state.hidden.has(f)) {
        const inWindow = state.series.get(f).filter(([t]) => t >= x0);
        const step = Math.ceil(inWindow.length / MAX_DRAWN);
        const pts = inWindow.filter((_, k) => (inWindow.length - 1 - k) % step === 0)
          .map(([t, v]) => `${X(t).toFixed(1)},${Y(v).toFixed(1)}`);
        svg('polyline', { class: 'series', points: pts.join(' '), stroke: COLORS[i], 'data-field': f, 'data-points': pts.length }, root);
      }
      const item = document.createElement('span');
      item.className = state.hidden.has(f) ? 'item off' : 'item';
      item.title = state.hidden.has(f) ? 'click to draw it' : 'click to hide it';
      item.addEventListener('click', () => {
        if (state.hidden.has(f)) state.hidden.delete(f); else state.hidden.add(f);
        drawPlot();
      });
      item.setAttribute('data-field', f);
      const sw = document.createElement('span');
      sw.className = 'swatch';
      sw.style.background = COLORS[i];
      item.appendChild(sw);
      const last = state.series.get(f)[state.series.get(f).length - 1];
      item.appendChild(document.createTextNode(`${f} = ${fmt(last ? last[1] : NaN)}`));
      legend.appendChild(item);
    });
    if (fields.length > drawn.length) {
      const more = document.createElement('span');
      more.textContent = `and ${fields.length - drawn.length} more fields, not drawn: ${fields.slice(MAX_FIELDS).join(', ')}`;
      legend.appendChild(more);
    }
  }

  // ------------------------------------------------------------------ events

  function connect(name) {
    if (state.events) state.events.close();
    const url = name === null ? '/api/events' : '/api/events/' + encodeURIComponent(name);
    const es = new EventSource(url);
    es.addEventListener('figures', (e) => onFigures(JSON.parse(e.data)));
    es.addEventListener('values', (e) => onValues(JSON.parse(e.data)));
    es.onerror = () => {
      $('state').textContent = es.readyState === EventSource.CLOSED
        ? 'disconnected: reload the page when the inspector is back'
        : 'disconnected: retrying…';
      $('state').classList.add('down');
    };
    state.events = es;
  }

  $('plot-choice').addEventListener('change', (e) => choose(e.target.value));
  window.addEventListener('resize', drawPlot);
  loadTopology();
})();
