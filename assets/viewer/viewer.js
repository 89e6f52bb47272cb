// footslam view: draws the runs of data.js (window.FOOTSLAM_VIEW) with Leaflet.
//
// Each layer of each run becomes one overlay in the layer list. Features with a `level`
// are drawn only while their level is selected (the level switcher appears when the page
// holds several); paths carry a marker the time slider moves. The page records what it drew
// and any error in #status (see index.html), which the tests read.
(function () {
  'use strict';
  // A page opened from disk hides the details of errors from window.onerror ("Script
  // error."): catch them here, with their message and stack.
  try {
    drawView();
  } catch (e) {
    window.FOOTSLAM_ERRORS.push(String(e && e.stack ? e.stack : e));
    window.footslamStatus();
  }
})();

function drawView() {
  'use strict';

  const VIEW = window.FOOTSLAM_VIEW;
  const ALL = 'all';
  const TRACK_COLOURS = ['#e6194b', '#4363d8', '#f58231', '#911eb4', '#0aa5a5', '#f032e6', '#9a6324', '#000075'];
  const TRUTH_COLOUR = '#1b9e3b';
  const DEAD_RECKONING_COLOUR = '#777777';
  const GPS_COLOUR = '#ff8c00';
  // Viridis, as the project's pictures shade learned maps (map.png).
  const VIRIDIS = ['#440154', '#482878', '#3e4989', '#31688e', '#26828e', '#1f9e89', '#35b779', '#6ece58', '#b5de2b', '#fde725'];
  // Weak to strong signal: blue to red (RdYlBu reversed).
  const RSSI = ['#313695', '#4575b4', '#74add1', '#abd9e9', '#e0f3f8', '#fee090', '#fdae61', '#f46d43', '#d73027', '#a50026'];
  const RSSI_RANGE = [-100, -40];
  // Transition arrows appear when a hexagon's radius is this many pixels on screen.
  const ARROW_MIN_PIXELS = 14;

  // ---------- colour ramps ----------
  function hexToRgb(h) { return [1, 3, 5].map(i => parseInt(h.slice(i, i + 2), 16)); }
  function ramp(stops, f) {
    const x = Math.min(1, Math.max(0, Number.isFinite(f) ? f : 0)) * (stops.length - 1);
    const i = Math.min(stops.length - 2, Math.floor(x));
    const a = hexToRgb(stops[i]);
    const b = hexToRgb(stops[i + 1]);
    const t = x - i;
    return 'rgb(' + a.map((v, k) => Math.round(v + (b[k] - v) * t)).join(',') + ')';
  }
  function gradient(stops) { return 'linear-gradient(to right, ' + stops.join(', ') + ')'; }
  function fmt(v, digits) { return Number(v).toFixed(digits); }
  function esc(text) {
    return String(text).replace(/[&<>"]/g, c => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
  }

  // ---------- the map ----------
  const map = L.map('map', { preferCanvas: true, zoomSnap: 0.25, zoomDelta: 0.5, maxZoom: 28, minZoom: 2 });
  // Panes keep the drawing order whatever is switched on or off: plans under maps under paths.
  [['fs-basemap', 250], ['fs-plans', 405], ['fs-radio', 410], ['fs-maps', 415], ['fs-uncertainty', 430],
    ['fs-paths', 440], ['fs-truth', 445], ['fs-arrows', 450], ['fs-markers', 460]].forEach(([name, z]) => {
    map.createPane(name).style.zIndex = String(z);
  });

  const runs = VIEW.runs;
  const several = runs.length > 1;
  const origin = runs.length ? runs[0] : null;
  const allLevels = Array.from(new Set([].concat(...runs.map(r => [].concat(...r.layers.map(l => l.levels))))))
    .sort((a, b) => a - b);
  let currentLevel = allLevels.length > 1 ? allLevels[0] : ALL;
  let currentBssid = null;
  const views = [];
  const bounds = L.latLngBounds([]);

  function onLevel(level) { return currentLevel === ALL || level === undefined || level === null || level === currentLevel; }

  // ---------- layers ----------
  // A layer's Leaflet pieces, grouped by level (`null`: on every level), swapped into one
  // group (the overlay of the layer list) when the level changes.
  class View {
    constructor(run, spec) {
      this.run = run;
      this.spec = spec;
      this.name = several ? run.name + ' · ' + spec.name : spec.name;
      this.group = L.layerGroup();
      this.byLevel = new Map();
      this.drawn = 0;
      this.shown = spec.kind !== 'dead_reckoning' && !walkMapUnderMerged(run, spec);
      this.colour = null;
    }
    piece(level) {
      const key = level === undefined ? null : level;
      if (!this.byLevel.has(key)) { this.byLevel.set(key, L.layerGroup()); }
      return this.byLevel.get(key);
    }
    add(level, layer) {
      this.piece(level).addLayer(layer);
      this.drawn += 1;
      // A circle's bounds need the map; its centre will do.
      if (layer.getLatLng) { bounds.extend(layer.getLatLng()); } else if (layer.getBounds) { bounds.extend(layer.getBounds()); }
    }
    setLevel() {
      this.group.clearLayers();
      this.byLevel.forEach((piece, level) => { if (onLevel(level)) { this.group.addLayer(piece); } });
    }
  }

  // A batch's walk maps, plans and field maps start hidden under the merged ones (one click away in the
  // layer list): three maps on top of each other hide each other.
  function walkMapUnderMerged(run, spec) {
    const merged = run.layers.some(l => /^merged(_plan)?\.geojson$/.test(l.file));
    return merged && /^walk-\d+\//.test(spec.file) && ['hex_map', 'plan', 'field_map'].includes(spec.kind);
  }

  function featureLevel(f) { const l = f.properties && f.properties.level; return Number.isInteger(l) ? l : null; }

  function geojsonPieces(view, collection, options) {
    for (const feature of collection.features || []) {
      if (!feature.geometry) { continue; }
      const layer = L.geoJSON(feature, options);
      view.add(featureLevel(feature), layer);
    }
  }

  function drawPlan(view) {
    const outline = view.spec.kind === 'outline';
    const learned = /(^|\/)(merged_)?plan\.geojson$/.test(view.spec.file);
    view.learned = learned;
    geojsonPieces(view, view.spec.data.geojson, {
      pane: 'fs-plans',
      style: () => outline
        ? { color: '#555', weight: 2, dashArray: '6 5', fill: false }
        : { color: learned ? '#8c7a55' : '#8a8a80', weight: 1, fillColor: learned ? '#efe3c4' : '#ffffff', fillOpacity: 0.9 },
      onEachFeature: (f, layer) => {
        const p = f.properties || {};
        layer.bindTooltip(esc(view.name) + (p.name ? ': ' + esc(p.name) : '') + (p.level !== undefined ? ' · level ' + p.level : ''), { sticky: true });
      },
    });
  }

  function drawHexMap(view) {
    const collection = view.spec.data.geojson;
    const features = collection.features || [];
    const maxVisits = features.reduce((m, f) => Math.max(m, (f.properties && f.properties.visits) || 0), 1);
    view.maxVisits = maxVisits;
    const shade = v => ramp(VIRIDIS, Math.log(1 + v) / Math.log(1 + maxVisits));
    view.hexRadius = collection.hex_radius || 0.5;
    view.arrows = new Map();
    for (const f of features) {
      if (!f.geometry) { continue; }
      const p = f.properties || {};
      const level = featureLevel(f);
      const layer = L.geoJSON(f, {
        pane: 'fs-maps',
        style: () => ({ color: '#2b2b2b', weight: 0.4, opacity: 0.6, fillColor: shade(p.visits || 0), fillOpacity: 0.8 }),
      });
      layer.bindTooltip('hexagon ' + p.q + ',' + p.r + ' · ' + (p.visits || 0) + ' visits' + (level !== null ? ' · level ' + level : ''), { sticky: true });
      view.add(level, layer);
      const arrows = hexArrows(view, f);
      if (arrows) {
        if (!view.arrows.has(level)) { view.arrows.set(level, L.layerGroup()); }
        view.arrows.get(level).addLayer(arrows);
      }
    }
    view.arrowsShown = false;
  }

  // Arrows from a hexagon's centre across each edge it was left by: edge k faces 60°·k
  // counter-clockwise from east (map.geojson's `edge_order`), length by the edge's share.
  function hexArrows(view, feature) {
    const counts = (feature.properties && feature.properties.counts) || [];
    const total = counts.reduce((a, b) => a + b, 0);
    if (!total || feature.geometry.type !== 'Polygon') { return null; }
    const ring = feature.geometry.coordinates[0].slice(0, -1);
    const lon = ring.reduce((a, c) => a + c[0], 0) / ring.length;
    const lat = ring.reduce((a, c) => a + c[1], 0) / ring.length;
    const [mLon, mLat] = view.run.metres_per_degree;
    const r = view.hexRadius;
    const at = (x, y) => [lat + y / mLat, lon + x / mLon];
    const lines = [];
    counts.forEach((n, k) => {
      if (!n) { return; }
      const a = k * Math.PI / 3;
      // From near the centre towards the edge's midpoint (√3/2 r away): the larger the
      // share of the hexagon's exits, the closer the tip comes to the edge.
      const len = r * (0.3 + 0.55 * n / total);
      const [dx, dy] = [Math.cos(a), Math.sin(a)];
      const tail = [dx * 0.12 * r, dy * 0.12 * r];
      const tip = [dx * len, dy * len];
      const head = 0.18 * r;
      const left = [tip[0] - head * Math.cos(a - 0.55), tip[1] - head * Math.sin(a - 0.55)];
      const right = [tip[0] - head * Math.cos(a + 0.55), tip[1] - head * Math.sin(a + 0.55)];
      lines.push([at(tail[0], tail[1]), at(tip[0], tip[1])], [at(left[0], left[1]), at(tip[0], tip[1]), at(right[0], right[1])]);
    });
    return L.polyline(lines, { pane: 'fs-arrows', color: '#111111', weight: 1.5, opacity: 0.85, interactive: false });
  }

  function hexRadiusPixels(view) {
    const c = map.getCenter();
    const metresPerPixel = 40075016.686 * Math.cos(c.lat * Math.PI / 180) / Math.pow(2, map.getZoom() + 8);
    return view.hexRadius / metresPerPixel;
  }

  function updateArrows() {
    for (const view of views) {
      if (view.spec.kind !== 'hex_map') { continue; }
      const show = hexRadiusPixels(view) >= ARROW_MIN_PIXELS;
      view.arrows.forEach((group, level) => {
        const wanted = show && onLevel(level);
        if (wanted && !view.group.hasLayer(group)) { view.group.addLayer(group); }
        if (!wanted && view.group.hasLayer(group)) { view.group.removeLayer(group); }
      });
    }
  }

  function drawRadioMap(view) {
    const layers = [];
    geojsonPieces(view, view.spec.data.geojson, {
      pane: 'fs-radio',
      style: f => radioStyle(f),
      onEachFeature: (f, layer) => {
        layers.push(layer);
        layer.bindTooltip(() => radioTooltip(view, f), { sticky: true });
      },
    });
    view.restyle = () => layers.forEach(l => l.setStyle(radioStyle(l.feature)));
    const counts = new Map();
    for (const f of view.spec.data.geojson.features || []) {
      for (const bssid of Object.keys((f.properties && f.properties.aps) || {})) {
        counts.set(bssid, (counts.get(bssid) || 0) + 1);
      }
    }
    view.bssids = counts;
  }

  function radioStyle(f) {
    const p = f.properties || {};
    const ap = currentBssid && p.aps ? p.aps[currentBssid] : null;
    if (ap) {
      const x = (ap.mean - RSSI_RANGE[0]) / (RSSI_RANGE[1] - RSSI_RANGE[0]);
      return { color: '#555', weight: 0.5, fillColor: ramp(RSSI, x), fillOpacity: 0.8 };
    }
    return { color: '#888', weight: 0.5, fill: true, fillColor: '#cccccc', fillOpacity: p.scans ? 0.25 : 0.08 };
  }

  function radioTooltip(view, f) {
    const p = f.properties || {};
    const ap = currentBssid && p.aps ? p.aps[currentBssid] : null;
    let text = esc(view.name) + ' · cell ' + esc(p.cell) + (p.level !== undefined ? ' · level ' + p.level : '') + ' · ' + (p.scans || 0) + ' scans';
    if (currentBssid) {
      text += '<br>' + esc(currentBssid) + ': ' + (ap ? fmt(ap.mean, 1) + ' dBm (' + ap.n + ' readings)' : 'not heard');
    }
    return text;
  }

  function drawFieldMap(view) {
    const values = (view.spec.data.geojson.features || []).map(f => f.properties && f.properties.magnitude_ut).filter(Number.isFinite).sort((a, b) => a - b);
    const lo = values.length ? values[Math.floor(0.02 * (values.length - 1))] : 0;
    const hi = values.length ? values[Math.ceil(0.98 * (values.length - 1))] : 1;
    view.range = [lo, hi];
    geojsonPieces(view, view.spec.data.geojson, {
      pane: 'fs-maps',
      style: f => ({ color: '#333', weight: 0.3, fillColor: ramp(VIRIDIS, (f.properties.magnitude_ut - lo) / Math.max(1e-9, hi - lo)), fillOpacity: 0.8 }),
      onEachFeature: (f, layer) => layer.bindTooltip(fmt(f.properties.magnitude_ut, 1) + ' µT · ' + f.properties.readings + ' readings', { sticky: true }),
    });
  }

  // Consecutive points on one level (and of one certainty) make one line.
  function segments(points) {
    const out = [];
    let current = null;
    for (const p of points) {
      const key = (p.level === undefined ? 'x' : p.level) + '/' + (p.certain === false ? 'u' : 'c');
      if (!current || current.key !== key) {
        if (current && current.level === p.level) { current.points.push([p.lat, p.lon]); }
        current = { key: key, level: p.level, uncertain: p.certain === false, points: [] };
        out.push(current);
      }
      current.points.push([p.lat, p.lon]);
    }
    return out;
  }

  // One colour per walk: a folder's smoothed and filtered tracks share it.
  const walkColours = new Map();
  function trackColour(view) {
    const key = view.run.name + '/' + view.spec.file.replace(/[^/]*$/, '');
    if (!walkColours.has(key)) { walkColours.set(key, TRACK_COLOURS[walkColours.size % TRACK_COLOURS.length]); }
    return walkColours.get(key);
  }

  function drawPath(view) {
    const kind = view.spec.kind;
    const points = view.spec.data.path;
    view.points = points;
    if (kind === 'truth' || kind === 'waypoints') {
      view.colour = TRUTH_COLOUR;
    } else if (kind === 'gps_fixes') {
      view.colour = GPS_COLOUR;
    } else if (kind === 'dead_reckoning') {
      view.colour = DEAD_RECKONING_COLOUR;
    } else {
      view.colour = trackColour(view);
    }
    const dots = kind === 'waypoints' || kind === 'gps_fixes';
    if (dots) {
      points.forEach((p, i) => {
        const m = L.circleMarker([p.lat, p.lon], { pane: 'fs-truth', radius: kind === 'waypoints' ? 5 : 3.5, color: '#fff', weight: 1.2, fillColor: view.colour, fillOpacity: 1 });
        m.bindTooltip(esc(view.name) + ' ' + (i + 1) + ' · t = ' + fmt(p.t, 1) + ' s' + (p.level !== undefined ? ' · level ' + p.level : '') + (p.spread !== undefined && kind === 'gps_fixes' ? ' · accuracy ' + fmt(p.spread, 1) + ' m' : ''));
        view.add(p.level, m);
      });
    } else {
      const style = {
        truth: { pane: 'fs-truth', weight: 2, dashArray: '6 4' },
        dead_reckoning: { pane: 'fs-paths', weight: 1.5, dashArray: '3 4' },
        filtered_track: { pane: 'fs-paths', weight: 1.6, dashArray: '7 4', opacity: 0.75 },
        track: { pane: 'fs-paths', weight: 2.6, opacity: 0.95 },
      }[kind];
      for (const s of segments(points)) {
        const line = L.polyline(s.points, Object.assign({ color: view.colour }, style, s.uncertain ? { dashArray: '2 5', opacity: 0.6 } : {}));
        line.bindTooltip(esc(view.name) + (s.level !== undefined ? ' · level ' + s.level : '') + (s.uncertain ? ' · uncertain' : ''), { sticky: true });
        view.add(s.level, line);
      }
    }
    // Each step's spread (a GPS fix's accuracy) as a faint disc.
    for (const p of points) {
      if (!(p.spread > 0)) { continue; }
      const c = L.circle([p.lat, p.lon], { pane: 'fs-uncertainty', radius: p.spread, stroke: false, fillColor: view.colour, fillOpacity: kind === 'gps_fixes' ? 0.05 : 0.1 });
      c.bindTooltip('t = ' + fmt(p.t, 1) + ' s · ' + (kind === 'gps_fixes' ? 'accuracy ' : 'spread ') + fmt(p.spread, 2) + ' m' + (p.certain === false ? ' · uncertain' : ''), { sticky: true });
      view.add(p.level, c);
    }
    if (points.length && !dots) {
      view.marker = L.circleMarker([points[0].lat, points[0].lon], { pane: 'fs-markers', radius: 6, color: '#fff', weight: 2, fillColor: view.colour, fillOpacity: 1 });
      view.marker.bindTooltip(esc(view.name));
    }
  }

  const DRAW = {
    plan: drawPlan, outline: drawPlan, hex_map: drawHexMap, radio_map: drawRadioMap, field_map: drawFieldMap,
    track: drawPath, filtered_track: drawPath, dead_reckoning: drawPath, truth: drawPath, waypoints: drawPath, gps_fixes: drawPath,
  };

  // ---------- time ----------
  // The point of a path at time t: interpolated between its rows; null outside its span.
  function pointAt(points, t) {
    if (!points.length || t < points[0].t || t > points[points.length - 1].t) { return null; }
    let lo = 0;
    let hi = points.length - 1;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (points[mid].t <= t) { lo = mid; } else { hi = mid; } }
    const a = points[lo];
    const b = points[hi];
    const f = b.t > a.t ? Math.min(1, Math.max(0, (t - a.t) / (b.t - a.t))) : 0;
    return { lat: a.lat + (b.lat - a.lat) * f, lon: a.lon + (b.lon - a.lon) * f, level: f < 0.5 ? a.level : b.level };
  }

  // Times on a walk's own clock read as seconds; Unix times (real recordings) as the UTC
  // time of day and the seconds since the slider's start.
  let timeStart = 0;
  function timeText(t) {
    if (timeStart < 1e8) { return 't = ' + fmt(t, 1) + ' s'; }
    return new Date(t * 1000).toISOString().slice(11, 21) + ' UTC (+' + fmt(t - timeStart, 1) + ' s)';
  }
  let timeLabel = null;
  let followBox = null;
  function setTime(t) {
    if (timeLabel) { timeLabel.textContent = timeText(t); }
    const leader = views.find(v => v.marker && v.spec.kind === 'track') || views.find(v => v.marker);
    if (followBox && followBox.checked && leader && currentLevel !== ALL) {
      const p = pointAt(leader.points, t);
      if (p && p.level !== undefined && p.level !== currentLevel) { setLevel(p.level); }
    }
    for (const view of views) {
      if (!view.marker) { continue; }
      const p = pointAt(view.points, t);
      const visible = p && onLevel(p.level);
      if (visible) {
        view.marker.setLatLng([p.lat, p.lon]);
        if (!view.group.hasLayer(view.marker)) { view.group.addLayer(view.marker); }
      } else if (view.group.hasLayer(view.marker)) {
        view.group.removeLayer(view.marker);
      }
    }
  }

  // ---------- levels ----------
  let levelButtons = [];
  let slider = null;
  function setLevel(level) {
    currentLevel = level;
    views.forEach(v => v.setLevel());
    updateArrows();
    levelButtons.forEach(b => b.classList.toggle('fs-active', String(b.dataset.level) === String(level)));
    if (slider) { setTime(Number(slider.value)); }
  }

  // ---------- controls ----------
  function panel() {
    const control = L.control({ position: 'topleft' });
    control.onAdd = () => {
      const div = L.DomUtil.create('div', 'fs-panel');
      L.DomEvent.disableClickPropagation(div);
      L.DomEvent.disableScrollPropagation(div);
      const h = document.createElement('h1');
      h.textContent = runs.map(r => r.name).join(' · ');
      div.appendChild(h);
      if (allLevels.length > 1) { div.appendChild(levelRow()); }
      const radios = views.filter(v => v.bssids);
      if (radios.length) { div.appendChild(bssidRow(radios)); }
      const paths = views.filter(v => v.marker);
      if (paths.length) { div.appendChild(timeRow(paths)); }
      return div;
    };
    control.addTo(map);
  }

  function levelRow() {
    const row = document.createElement('div');
    row.className = 'fs-row fs-levels';
    row.innerHTML = '<label>Level</label>';
    for (const level of allLevels.concat([ALL])) {
      const b = document.createElement('button');
      b.type = 'button';
      b.dataset.level = String(level);
      b.textContent = level === ALL ? 'all' : String(level);
      b.title = level === ALL ? 'every level at once' : 'show level ' + level;
      b.addEventListener('click', () => setLevel(level));
      row.appendChild(b);
      levelButtons.push(b);
    }
    return row;
  }

  function bssidRow(radios) {
    const counts = new Map();
    radios.forEach(v => v.bssids.forEach((n, b) => counts.set(b, (counts.get(b) || 0) + n)));
    const bssids = Array.from(counts.keys()).sort((a, b) => counts.get(b) - counts.get(a) || a.localeCompare(b));
    const row = document.createElement('div');
    row.className = 'fs-row';
    row.innerHTML = '<label for="fs-bssid">Access point</label>';
    const select = document.createElement('select');
    select.id = 'fs-bssid';
    select.innerHTML = '<option value="">(cells scanned)</option>' +
      bssids.map(b => '<option value="' + esc(b) + '">' + esc(b) + ' (' + counts.get(b) + ' cells)</option>').join('');
    select.addEventListener('change', () => {
      currentBssid = select.value || null;
      radios.forEach(v => v.restyle());
      legend.update();
    });
    row.appendChild(select);
    currentBssid = bssids.length ? bssids[0] : null;
    select.value = currentBssid || '';
    radios.forEach(v => v.restyle());
    return row;
  }

  function timeRow(paths) {
    const t0 = Math.min(...paths.map(v => v.points[0].t));
    const t1 = Math.max(...paths.map(v => v.points[v.points.length - 1].t));
    timeStart = t0;
    const row = document.createElement('div');
    row.className = 'fs-row';
    row.innerHTML = '<label for="fs-time">Time</label>';
    slider = document.createElement('input');
    slider.type = 'range';
    slider.id = 'fs-time';
    slider.min = String(t0);
    slider.max = String(t1);
    slider.step = String(Math.max(0.01, (t1 - t0) / 2000));
    slider.value = String(t0);
    timeLabel = document.createElement('span');
    timeLabel.className = 'fs-time';
    slider.addEventListener('input', () => setTime(Number(slider.value)));
    row.appendChild(slider);
    row.appendChild(timeLabel);
    if (allLevels.length > 1) {
      const follow = document.createElement('label');
      followBox = document.createElement('input');
      followBox.type = 'checkbox';
      followBox.checked = true;
      follow.appendChild(followBox);
      follow.appendChild(document.createTextNode(' follow the floor'));
      follow.title = 'switch to the floor of the track at the slider\'s time';
      row.appendChild(follow);
    }
    return row;
  }

  const legend = L.control({ position: 'bottomleft' });
  legend.onAdd = () => {
    legend.div = L.DomUtil.create('div', 'fs-panel fs-legend');
    legend.update();
    return legend.div;
  };
  legend.update = () => {
    if (!legend.div) { return; }
    const parts = [];
    const rampBlock = (title, stops, lo, hi) => parts.push('<div class="fs-title">' + title + '</div><span class="fs-ramp" style="background:' +
      gradient(stops) + '"></span><div class="fs-ramp-labels"><span>' + lo + '</span><span>' + hi + '</span></div>');
    const hex = views.filter(v => v.spec.kind === 'hex_map');
    if (hex.length) { rampBlock('Hexagon visits (log scale)', VIRIDIS, 0, Math.max(...hex.map(v => v.maxVisits))); }
    if (views.some(v => v.spec.kind === 'radio_map')) {
      if (currentBssid) { rampBlock('Mean RSSI of ' + esc(currentBssid) + ' (dBm)', RSSI, RSSI_RANGE[0], RSSI_RANGE[1]); } else { parts.push('<div><span class="fs-box" style="background:#ccc"></span>radio-map cells (shaded: scanned)</div>'); }
    }
    views.filter(v => v.spec.kind === 'field_map' && map.hasLayer(v.group)).forEach(v => rampBlock('Field magnitude (µT)', VIRIDIS, fmt(v.range[0], 1), fmt(v.range[1], 1)));
    const plans = views.filter(v => v.spec.kind === 'plan');
    if (plans.some(v => !v.learned)) { parts.push('<div><span class="fs-box" style="background:#fff"></span>floor plan</div>'); }
    if (plans.some(v => v.learned)) { parts.push('<div><span class="fs-box" style="background:#efe3c4"></span>learned plan</div>'); }
    // Truth and waypoints share one colour: several such layers make one entry.
    const shared = kind => views.filter(v => v.spec.kind === kind).length > 1;
    for (const v of views) {
      if (!v.colour || !map.hasLayer(v.group)) { continue; }
      const label = esc(['truth', 'waypoints', 'gps_fixes'].includes(v.spec.kind) && shared(v.spec.kind) ? v.spec.kind.replace('gps_fixes', 'GPS fixes') : v.name);
      if (v.spec.kind === 'waypoints' || v.spec.kind === 'gps_fixes') {
        parts.push('<div><span class="fs-dot" style="background:' + v.colour + '"></span>' + label + '</div>');
      } else {
        const dash = { truth: 'dashed', dead_reckoning: 'dotted', filtered_track: 'dashed' }[v.spec.kind] || 'solid';
        parts.push('<div><span class="fs-swatch" style="border-top-color:' + v.colour + ';border-top-style:' + dash + '"></span>' + label + '</div>');
      }
    }
    if (views.some(v => v.points && v.points.some(p => p.spread > 0))) { parts.push('<div><span class="fs-dot" style="background:rgba(90,90,90,0.2);box-shadow:none"></span>uncertainty: disc of the step\'s spread</div>'); }
    if (hex.length) { parts.push('<div style="font-size:11px;color:#555">zoom in for transition arrows (black)</div>'); }
    legend.div.innerHTML = parts.filter((p, i) => parts.indexOf(p) === i).join('');
  };

  // Latitude/longitude and metres east/north of the (first) run's origin under the pointer.
  function readout() {
    const control = L.control({ position: 'bottomleft' });
    control.onAdd = () => {
      const div = L.DomUtil.create('div', 'fs-panel fs-readout');
      div.textContent = 'move over the map for coordinates';
      map.on('mousemove', e => {
        const { lat, lng } = e.latlng;
        let text = fmt(lat, 7) + '°, ' + fmt(lng, 7) + '°';
        if (origin) {
          const [mLon, mLat] = origin.metres_per_degree;
          const x = (lng - origin.origin.lon) * mLon;
          const y = (lat - origin.origin.lat) * mLat;
          text += ' · x ' + fmt(x, 2) + ' m, y ' + fmt(y, 2) + ' m' + (several ? ' (' + origin.name + ')' : '');
        }
        div.textContent = text;
      });
      return div;
    };
    control.addTo(map);
  }

  function basemap(layerControl) {
    const b = VIEW.basemap;
    if (!b) { return; }
    if (b.type === 'tiles') {
      const tiles = L.tileLayer(b.url, { maxNativeZoom: 19, maxZoom: 28, attribution: esc(b.attribution || '') });
      // Tiles loaded and failed, for the page's report (a failed tile is also an error).
      const counts = { type: 'tiles', tiles_loaded: 0, tiles_failed: 0 };
      tiles.on('tileload', () => { counts.tiles_loaded += 1; window.footslamStatus({ basemap: counts }); });
      tiles.on('tileerror', (e) => {
        counts.tiles_failed += 1;
        window.FOOTSLAM_ERRORS.push('basemap tile failed: ' + (e.tile && e.tile.src));
        window.footslamStatus({ basemap: counts });
      });
      tiles.addTo(map);
      layerControl.addOverlay(tiles, 'basemap');
    } else if (b.type === 'image') {
      const image = L.imageOverlay(b.file, b.bounds, { pane: 'fs-basemap', opacity: 0.85 });
      image.addTo(map);
      layerControl.addOverlay(image, 'basemap image');
      if (!bounds.isValid()) { bounds.extend(b.bounds); }
    }
  }

  // ---------- build ----------
  // The layer list stays open unless it is long (a batch of many walks).
  const overlays = runs.reduce((n, r) => n + r.layers.length, 0);
  const layerControl = L.control.layers(null, null, { collapsed: overlays > 14, position: 'topright' }).addTo(map);
  for (const run of runs) {
    for (const spec of run.layers) {
      const view = new View(run, spec);
      DRAW[spec.kind](view);
      views.push(view);
    }
  }
  basemap(layerControl);
  for (const view of views) {
    view.setLevel();
    if (view.shown) { view.group.addTo(map); }
    layerControl.addOverlay(view.group, esc(view.name));
  }
  L.control.scale({ metric: true, imperial: false, maxWidth: 200 }).addTo(map);
  panel();
  readout();
  legend.addTo(map);
  if (bounds.isValid()) { map.fitBounds(bounds, { padding: [30, 30] }); } else { map.setView([0, 0], 18); }
  map.on('zoomend', updateArrows);
  map.on('overlayadd overlayremove', () => legend.update());
  setLevel(currentLevel);
  updateArrows();
  if (slider) { setTime(Number(slider.value)); }
  map.attributionControl.setPrefix('<a href="https://leafletjs.com">Leaflet</a> · footslam ' + esc(VIEW.version));

  // `index.html#selftest` (the tests): work every control once — each level, the slider
  // at its start, middle and end, each access point, a zoom to the arrows, the pointer's
  // read-out, each overlay off and on — then return to the opening view.
  let exercised = null;
  if (window.location.hash === '#selftest') {
    exercised = exercise();
  }

  function exercise() {
    const start = { level: currentLevel, center: map.getCenter(), zoom: map.getZoom() };
    allLevels.concat([ALL]).forEach(setLevel);
    const times = [];
    if (slider) {
      for (const f of [0, 0.5, 1]) {
        slider.value = String(Number(slider.min) + f * (Number(slider.max) - Number(slider.min)));
        slider.dispatchEvent(new Event('input'));
        times.push(timeLabel.textContent);
      }
    }
    const select = document.getElementById('fs-bssid');
    const bssids = select ? Array.from(select.options).map(o => o.value) : [];
    bssids.concat(bssids.length ? [bssids[Math.min(1, bssids.length - 1)]] : []).forEach(b => {
      select.value = b;
      select.dispatchEvent(new Event('change'));
    });
    map.setZoom(start.zoom + 5, { animate: false });
    const arrows = views.filter(v => v.arrows).reduce((n, v) => n + Array.from(v.arrows.values()).filter(g => v.group.hasLayer(g)).length, 0);
    map.fire('mousemove', { latlng: map.getCenter() });
    const readoutText = document.querySelector('.fs-readout').textContent;
    views.forEach(v => { const on = map.hasLayer(v.group); map.removeLayer(v.group); if (on) { map.addLayer(v.group); } });
    setLevel(start.level);
    map.setView(start.center, start.zoom, { animate: false });
    if (slider) { slider.value = slider.min; setTime(Number(slider.min)); }
    return { levels: allLevels.length, times: times, access_points: bssids.length, arrow_groups: arrows, readout: readoutText };
  }

  window.footslamStatus({
    exercised: exercised,
    ready: true,
    level: currentLevel,
    levels: allLevels,
    layers: views.map(v => ({ run: v.run.name, name: v.spec.name, kind: v.spec.kind, features: v.spec.features, drawn: v.drawn, shown: v.shown })),
  });
}
