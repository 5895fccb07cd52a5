// The stcweave page: draws a hex mesh with three.js and replays its weave. Everything it
// needs is in this file: the data (JSON, typed arrays as base64), three.js and this script.
// It draws the faces of the visible hexes that no visible hex covers, so that replay, "show
// only" and the clipping plane (which removes whole hexes) show the hexes as solids.
// Status for tests: the #stcweave-status element's data-* attributes (see docs/viewer.md).
(function () {
  'use strict';
  var t0 = performance.now();
  var statusEl = document.getElementById('stcweave-status');
  function setStatus(key, value) { statusEl.setAttribute('data-' + key, String(value)); }

  var D = JSON.parse(document.getElementById('stcweave-data').textContent);
  function decode(text, Type) {
    if (text === undefined || text === null) return null;
    var bin = atob(text);
    var bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  // Integers: value - offset in the narrowest unsigned type (see page.cpp), to Int32Array.
  function ints(entry) {
    if (entry === undefined || entry === null) return null;
    var Type = { 1: Uint8Array, 2: Uint16Array, 4: Uint32Array }[entry.bytes];
    if (!Type) throw new Error('embedded integers of ' + entry.bytes + ' bytes');
    var raw = decode(entry.data, Type), out = new Int32Array(raw.length), offset = entry.offset;
    for (var i = 0; i < raw.length; i++) out[i] = raw[i] + offset;
    return out;
  }
  var m = D.hexes, n = D.nodes;
  document.getElementById('title').textContent = D.title;
  var P = decode(D.points, Float32Array);
  var H = ints(D.hex_nodes);
  var NB = ints(D.neighbours);
  var SJ = decode(D.scaled_jacobian, Float32Array);
  var SH = ints(D.sheet_ids);
  var CH = ints(D.chord_ids);
  var LAYER = ints(D.layer);
  var ORDER = ints(D.order);
  var SHRINK = ints(D.shrink);
  var DEPTH = ints(D.depth);
  var RULE = ints(D.rule);
  var RNODE = ints(D.rule_node);
  function expect(name, array, size) {
    if (array !== null && array.length !== size)
      throw new Error('embedded array ' + name + ' has ' + array.length + ' values, ' + size + ' expected');
  }
  expect('points', P, 3 * n); expect('hex_nodes', H, 8 * m); expect('neighbours', NB, 6 * m);
  expect('scaled_jacobian', SJ, m); expect('sheet_ids', SH, 3 * m); expect('chord_ids', CH, 3 * m);
  expect('layer', LAYER, m); expect('order', ORDER, m); expect('shrink', SHRINK, m);
  expect('depth', DEPTH, m); expect('rule', RULE, m); expect('rule_node', RNODE, m);
  var RANK = new Int32Array(m);
  for (var k = 0; k < m; k++) RANK[ORDER[k]] = k;
  var shrinkInfo = {};
  D.shrinks.forEach(function (r) { shrinkInfo[r.shrink] = r; });
  var shrinkSize = {};
  if (SHRINK) for (var h0 = 0; h0 < m; h0++) shrinkSize[SHRINK[h0]] = (shrinkSize[SHRINK[h0]] || 0) + 1;
  function distinct(array) {
    var seen = new Set();
    for (var i = 0; i < array.length; i++) if (array[i] >= 0) seen.add(array[i]);
    return seen.size;
  }

  // ---- hex topology (stc::kHexFaces, edge directions of hex_stc.hpp) ----
  var FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
  function direction(a, b) {
    var key = Math.min(a, b) * 8 + Math.max(a, b);
    if ([1, 19, 37, 55].indexOf(key) >= 0) return 0;  // 0-1, 3-2, 4-5, 7-6
    if ([10, 3, 46, 39].indexOf(key) >= 0) return 1;  // 1-2, 0-3, 5-6, 4-7
    return 2;                                         // 0-4, 1-5, 2-6, 3-7
  }
  var EDGE_DIR = FACES.map(function (f) {
    return f.map(function (a, i) { return direction(a, f[(i + 1) % 4]); });
  });
  var ALONG = EDGE_DIR.map(function (dirs) { return 3 - dirs[0] - dirs[1]; });

  // ---- centroids and bounds ----
  var C = new Float32Array(3 * m);
  var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (var i = 0; i < n; i++) {
    for (var c = 0; c < 3; c++) {
      lo[c] = Math.min(lo[c], P[3 * i + c]); hi[c] = Math.max(hi[c], P[3 * i + c]);
    }
  }
  for (var h = 0; h < m; h++) {
    for (var j = 0; j < 8; j++) {
      var v = H[8 * h + j];
      C[3 * h] += P[3 * v] / 8; C[3 * h + 1] += P[3 * v + 1] / 8; C[3 * h + 2] += P[3 * v + 2] / 8;
    }
  }
  if (n === 0) { lo = [0, 0, 0]; hi = [1, 1, 1]; }

  // ---- colours ----
  function hsl(hue, s, l) {
    var q = l < 0.5 ? l * (1 + s) : l + s - l * s, p = 2 * l - q;
    function f(t) {
      t = (t + 1) % 1;
      if (t < 1 / 6) return p + (q - p) * 6 * t;
      if (t < 1 / 2) return q;
      if (t < 2 / 3) return p + (q - p) * (2 / 3 - t) * 6;
      return p;
    }
    return [f(hue + 1 / 3), f(hue), f(hue - 1 / 3)];
  }
  function idColor(id) {
    if (id < 0) return [0.6, 0.6, 0.6];
    var hue = (id * 0.6180339887) % 1;
    return hsl(hue, 0.55 + 0.35 * ((id * 7) % 3) / 2, 0.45 + 0.15 * ((id * 5) % 3) / 2);
  }
  var RAMP = [[0.27, 0.0, 0.33], [0.23, 0.32, 0.55], [0.13, 0.57, 0.55], [0.37, 0.79, 0.38], [0.99, 0.91, 0.14]];
  function ramp(t) {
    t = Math.max(0, Math.min(1, t)) * (RAMP.length - 1);
    var a = Math.min(RAMP.length - 2, Math.floor(t)), u = t - a;
    return [0, 1, 2].map(function (c) { return RAMP[a][c] * (1 - u) + RAMP[a + 1][c] * u; });
  }
  // Scaled Jacobian: dark red when inverted (<= 0), then red -> yellow -> green -> blue on ]0, 1].
  var SJ_RAMP = [[0.85, 0.1, 0.1], [0.98, 0.6, 0.1], [0.95, 0.9, 0.2], [0.35, 0.75, 0.35], [0.2, 0.45, 0.85]];
  function sjColor(s) {
    if (!(s > 0)) return [0.45, 0.0, 0.05];
    var t = Math.min(1, s) * (SJ_RAMP.length - 1), a = Math.min(SJ_RAMP.length - 2, Math.floor(t)), u = t - a;
    return [0, 1, 2].map(function (c) { return SJ_RAMP[a][c] * (1 - u) + SJ_RAMP[a + 1][c] * u; });
  }
  function range(array) {
    var a = Infinity, b = -Infinity;
    if (array) for (var i = 0; i < array.length; i++) { a = Math.min(a, array[i]); b = Math.max(b, array[i]); }
    if (a > b) { a = 0; b = 1; }
    return [a, b];
  }
  var RANGES = { depth: range(DEPTH), layer: range(LAYER), step: [0, Math.max(1, m - 1)] };

  // ---- state ----
  var state = { step: m, color: 'sheets', edges: true, sheet: -1, chord: -1, clip: false,
                axis: 2, flip: false, at: 0.5, highlight: true, picked: -1 };
  var visible = new Uint8Array(m);
  var visibleCount = 0, drawnFaces = 0, triHex = new Int32Array(0);

  function hexColor(h) {
    switch (state.color) {
      case 'sj': return sjColor(SJ[h]);
      case 'depth': return DEPTH ? ramp((DEPTH[h] - RANGES.depth[0]) / Math.max(1, RANGES.depth[1] - RANGES.depth[0])) : [0.6, 0.6, 0.6];
      case 'layer': return ramp((LAYER[h] - RANGES.layer[0]) / Math.max(1, RANGES.layer[1] - RANGES.layer[0]));
      case 'step': return ramp(RANK[h] / RANGES.step[1]);
      case 'shrink': return SHRINK ? idColor(SHRINK[h]) : [0.6, 0.6, 0.6];
      default: return null;
    }
  }

  function computeVisible() {
    var axis = state.axis, at = lo[axis] + state.at * (hi[axis] - lo[axis]), sign = state.flip ? -1 : 1;
    visibleCount = 0;
    for (var h = 0; h < m; h++) {
      var show = RANK[h] < state.step;
      if (show && state.sheet >= 0) show = SH[3 * h] === state.sheet || SH[3 * h + 1] === state.sheet || SH[3 * h + 2] === state.sheet;
      if (show && state.chord >= 0) show = CH[3 * h] === state.chord || CH[3 * h + 1] === state.chord || CH[3 * h + 2] === state.chord;
      if (show && state.clip) show = (C[3 * h + axis] - at) * sign <= 0;
      visible[h] = show ? 1 : 0;
      visibleCount += show ? 1 : 0;
    }
  }

  // ---- three.js scene ----
  var container = document.getElementById('view');
  var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  var BACKGROUND = 0xf4f4f2;
  renderer.setClearColor(BACKGROUND, 1);
  container.appendChild(renderer.domElement);
  var scene = new THREE.Scene();
  var camera = new THREE.PerspectiveCamera(35, 1, 1e-3, 1e3);
  var centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  var radius = Math.max(1e-9, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  camera.near = radius / 100; camera.far = radius * 100;
  camera.position.copy(centre).add(new THREE.Vector3(1.1, -1.6, 1.0).normalize().multiplyScalar(radius / Math.sin(17.5 * Math.PI / 180)));
  camera.up.set(0, 0, 1);
  camera.lookAt(centre);
  scene.add(camera);
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  var light = new THREE.DirectionalLight(0xffffff, 0.6);
  light.position.set(0.3, 0.5, 1);
  camera.add(light);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  var material = new THREE.MeshLambertMaterial({ vertexColors: THREE.VertexColors, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
  var edgeMaterial = new THREE.LineBasicMaterial({ color: 0x202020, transparent: true, opacity: 0.45 });
  var mesh = null, lines = null;

  function resize() {
    var w = Math.max(1, container.clientWidth), hgt = Math.max(1, container.clientHeight);
    renderer.setSize(w, hgt);
    camera.aspect = w / hgt;
    camera.updateProjectionMatrix();
  }

  function rebuild() {
    computeVisible();
    var faces = 0;
    for (var h = 0; h < m; h++) {
      if (!visible[h]) continue;
      for (var f = 0; f < 6; f++) { var nb = NB[6 * h + f]; if (nb < 0 || !visible[nb]) faces++; }
    }
    drawnFaces = faces;
    var pos = new Float32Array(faces * 36), nor = new Float32Array(faces * 36), col = new Float32Array(faces * 36);
    var seg = new Float32Array(faces * 24);
    triHex = new Int32Array(faces * 4);
    var last = state.step > 0 && state.step <= m ? ORDER[state.step - 1] : -1;
    var replaying = state.highlight && state.step < m && last >= 0;
    var lastShrink = replaying && SHRINK ? SHRINK[last] : null;
    var p = 0, s = 0, t = 0, corner = [[0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (h = 0; h < m; h++) {
      if (!visible[h]) continue;
      var base = hexColor(h);
      if (replaying) {
        if (h === last) base = [0.9, 0.05, 0.05];
        else if (lastShrink !== null && SHRINK[h] === lastShrink) {
          var b0 = base || idColor(SH[3 * h]);
          base = [0.5 * b0[0] + 0.5, 0.5 * b0[1] + 0.3, 0.5 * b0[2]];
        }
      }
      for (f = 0; f < 6; f++) {
        nb = NB[6 * h + f];
        if (nb >= 0 && visible[nb]) continue;
        var face = FACES[f], cx = 0, cy = 0, cz = 0;
        for (var q = 0; q < 4; q++) {
          var v = H[8 * h + face[q]];
          corner[q][0] = P[3 * v]; corner[q][1] = P[3 * v + 1]; corner[q][2] = P[3 * v + 2];
          cx += corner[q][0] / 4; cy += corner[q][1] / 4; cz += corner[q][2] / 4;
        }
        var ax = corner[2][0] - corner[0][0], ay = corner[2][1] - corner[0][1], az = corner[2][2] - corner[0][2];
        var bx = corner[3][0] - corner[1][0], by = corner[3][1] - corner[1][1], bz = corner[3][2] - corner[1][2];
        var nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
        var len = Math.hypot(nx, ny, nz) || 1; nx /= len; ny /= len; nz /= len;
        for (q = 0; q < 4; q++) {
          var a = corner[q], b = corner[(q + 1) % 4], rgb = base;
          if (rgb === null) {
            rgb = state.color === 'layers' ? idColor(SH[3 * h + ALONG[f]]) : idColor(SH[3 * h + EDGE_DIR[f][q]]);
          }
          var tri = [cx, cy, cz, a[0], a[1], a[2], b[0], b[1], b[2]];
          for (var e = 0; e < 9; e++) { pos[p + e] = tri[e]; col[p + e] = rgb[e % 3]; }
          for (e = 0; e < 3; e++) { nor[p + 3 * e] = nx; nor[p + 3 * e + 1] = ny; nor[p + 3 * e + 2] = nz; }
          p += 9;
          seg[s] = a[0]; seg[s + 1] = a[1]; seg[s + 2] = a[2]; seg[s + 3] = b[0]; seg[s + 4] = b[1]; seg[s + 5] = b[2];
          s += 6;
          triHex[t++] = h;
        }
      }
    }
    if (mesh) { scene.remove(mesh); mesh.geometry.dispose(); }
    if (lines) { scene.remove(lines); lines.geometry.dispose(); }
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setAttribute('normal', new THREE.BufferAttribute(nor, 3));
    g.setAttribute('color', new THREE.BufferAttribute(col, 3));
    mesh = new THREE.Mesh(g, material);
    scene.add(mesh);
    var lg = new THREE.BufferGeometry();
    lg.setAttribute('position', new THREE.BufferAttribute(seg, 3));
    lines = new THREE.LineSegments(lg, edgeMaterial);
    lines.visible = state.edges;
    scene.add(lines);
    updateText();
    drawLegend();
    render();
  }

  function render() { renderer.render(scene, camera); }

  // ---- text, legend, histogram ----
  function el(id) { return document.getElementById(id); }
  function ruleName(h) {
    if (!RULE) return 'unknown rule';
    var code = RULE[h];
    return (D.rule_names && D.rule_names[String(code)]) || ('rule ' + code);
  }
  function updateText() {
    el('summary').textContent = m + ' hexes, ' + n + ' nodes, ' + D.sheets + ' sheets (' + D.blind_sheets +
      ' blind), ' + D.chords + ' chords (' + D.blind_chords + ' blind); showing ' + visibleCount + ' hexes.';
    var info = '';
    if (!D.history) info = 'The file has no weave data (creation_step): the replay follows the hex order of the file. ';
    if (state.step === 0) info += 'Step 0: no hex yet.';
    else {
      var h = ORDER[state.step - 1];
      info += 'Step ' + state.step + ' of ' + m + ': hex h' + h;
      if (RULE) info += ', made by ' + ruleName(h) + (RNODE && RNODE[h] >= 0 ? ' at front node n' + RNODE[h] + ' (the weave\'s numbering)' : '');
      if (SHRINK) {
        var r = shrinkInfo[SHRINK[h]];
        info += '; loop shrink ' + SHRINK[h] + ' (' + shrinkSize[SHRINK[h]] + ' hexes)';
        if (r) {
          info += ': loop ' + r.loop + ' to side ' + r.side + ', length ' + r.length + ', depth ' + r.depth +
            ', decided by ' + (r.decided_by || '?') + (r.failed ? ', ended blocked' : '');
        }
      }
      info += '.';
    }
    el('step-info').textContent = info;
  }
  function drawLegend() {
    var cv = el('legend'), g = cv.getContext('2d');
    g.clearRect(0, 0, cv.width, cv.height);
    g.fillStyle = '#333'; g.font = '11px sans-serif';
    var scalar = { sj: [0, 1, sjColor, 'scaled Jacobian (dark red: <= 0)'],
      depth: [RANGES.depth[0], RANGES.depth[1], null, DEPTH ? 'depth of the shrink' : 'no depth in the data'],
      layer: [RANGES.layer[0], RANGES.layer[1], null, 'layer'],
      step: [0, RANGES.step[1], null, 'creation step'] }[state.color];
    if (!scalar) {
      g.fillText(state.color === 'shrink' ? 'one colour per loop shrink' :
        state.color === 'layers' ? 'each face: the sheet parallel to it' :
        'each face: its two crossing sheets (' + D.sheets + ' sheets)', 2, 14);
      return;
    }
    for (var x = 0; x < cv.width - 4; x++) {
      var u = x / (cv.width - 5), rgb = scalar[2] ? scalar[2](Math.max(1e-6, u)) : ramp(u);
      g.fillStyle = 'rgb(' + rgb.map(function (c) { return Math.round(255 * c); }).join(',') + ')';
      g.fillRect(2 + x, 2, 1, 14);
    }
    g.fillStyle = '#333';
    g.fillText(String(scalar[0]), 2, 30);
    var right = String(Math.round(scalar[1] * 1000) / 1000);
    g.fillText(right, cv.width - 4 - g.measureText(right).width, 30);
    g.fillText(scalar[3], 60, 30);
  }
  function drawHistogram() {
    var bins = new Array(20).fill(0), min = Infinity, sum = 0, bad = 0, low = 0;
    for (var h = 0; h < m; h++) {
      var s = SJ[h];
      bins[Math.max(0, Math.min(19, Math.floor((s + 1) * 10)))]++;
      min = Math.min(min, s); sum += s; if (!(s > 0)) bad++; if (s < 0.2) low++;
    }
    var cv = el('histogram'), g = cv.getContext('2d'), top = Math.max.apply(null, bins.concat([1]));
    g.clearRect(0, 0, cv.width, cv.height);
    var w = (cv.width - 10) / 20;
    for (var b = 0; b < 20; b++) {
      var hgt = bins[b] > 0 ? Math.max(1, (cv.height - 30) * bins[b] / top) : 0;
      var rgb = sjColor(-1 + (b + 0.5) / 10);
      g.fillStyle = 'rgb(' + rgb.map(function (c) { return Math.round(255 * c); }).join(',') + ')';
      g.fillRect(5 + b * w, cv.height - 16 - hgt, w - 1, hgt);
    }
    g.fillStyle = '#333'; g.font = '11px sans-serif';
    g.fillText('-1', 2, cv.height - 3); g.fillText('0', cv.width / 2 - 3, cv.height - 3); g.fillText('1', cv.width - 9, cv.height - 3);
    g.fillText('max bin ' + top, 5, 11);
    el('quality').textContent = m ? 'min ' + min.toFixed(3) + ', mean ' + (sum / m).toFixed(3) + ', ' + bad +
      ' inverted (<= 0), ' + low + ' below 0.2' : 'no hex';
    return bins;
  }

  // ---- picking ----
  var raycaster = new THREE.Raycaster(), down = null;
  renderer.domElement.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', function (e) {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4 || !mesh) return;
    var r = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new THREE.Vector2((e.clientX - r.left) / r.width * 2 - 1, -(e.clientY - r.top) / r.height * 2 + 1), camera);
    var hits = raycaster.intersectObject(mesh);
    if (hits.length > 0) pick(triHex[hits[0].faceIndex]);
  });
  function pick(h) {
    state.picked = h;
    var box = el('pick-info');
    box.textContent = '';
    var text = 'hex h' + h + ': scaled Jacobian ' + SJ[h].toFixed(3) + ', layer ' + LAYER[h] +
      (D.history ? ', step ' + RANK[h] : '') + (SHRINK ? ', shrink ' + SHRINK[h] : '') +
      (DEPTH ? ', depth ' + DEPTH[h] : '') + (RULE ? ', ' + ruleName(h) : '') + '. Show only: ';
    box.appendChild(document.createTextNode(text));
    [0, 1, 2].forEach(function (d) {
      var b = document.createElement('button');
      b.textContent = 'sheet ' + SH[3 * h + d];
      b.onclick = function () { setFilter(SH[3 * h + d], -1); };
      box.appendChild(b);
    });
    [0, 1, 2].forEach(function (a) {
      var b = document.createElement('button');
      b.textContent = 'chord ' + CH[3 * h + a];
      b.onclick = function () { setFilter(-1, CH[3 * h + a]); };
      box.appendChild(b);
    });
  }
  function setFilter(sheet, chord) {
    state.sheet = sheet; state.chord = chord;
    el('sheet').value = sheet; el('chord').value = chord;
    rebuild();
  }

  // ---- controls ----
  var slider = el('step');
  slider.max = m; slider.value = m;
  slider.addEventListener('input', function () { state.step = Number(slider.value); rebuild(); });
  function setStep(k) { state.step = Math.max(0, Math.min(m, k)); slider.value = state.step; rebuild(); }
  el('prev').onclick = function () { stop(); setStep(state.step - 1); };
  el('next').onclick = function () { stop(); setStep(state.step + 1); };
  var timer = null;
  function stop() { if (timer) { clearInterval(timer); timer = null; el('play').textContent = 'play'; } }
  el('play').onclick = function () {
    if (timer) { stop(); return; }
    if (state.step >= m) setStep(0);
    el('play').textContent = 'pause';
    var by = Math.max(1, Math.round(m / 400));
    timer = setInterval(function () { if (state.step >= m) stop(); else setStep(state.step + by); }, 40);
  };
  el('highlight').onchange = function (e) { state.highlight = e.target.checked; rebuild(); };
  el('color').onchange = function (e) { state.color = e.target.value; rebuild(); };
  el('edges').onchange = function (e) { state.edges = e.target.checked; if (lines) lines.visible = state.edges; render(); };
  el('sheet').onchange = function (e) { setFilter(Number(e.target.value), -1); };
  el('chord').onchange = function (e) { setFilter(-1, Number(e.target.value)); };
  el('all').onclick = function () { setFilter(-1, -1); };
  el('clip').onchange = function (e) { state.clip = e.target.checked; rebuild(); };
  el('clip-axis').onchange = function (e) { state.axis = Number(e.target.value); rebuild(); };
  el('clip-flip').onchange = function (e) { state.flip = e.target.checked; rebuild(); };
  el('clip-at').addEventListener('input', function (e) { state.at = Number(e.target.value) / 1000; if (state.clip) rebuild(); });
  controls.addEventListener('change', render);
  window.addEventListener('resize', function () { resize(); render(); });

  // ---- options from the address (#color=sj&clip=z:0.5[:flip]&step=10&test) ----
  var options = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
    if (!kv) return;
    var parts = kv.split('=');
    options[decodeURIComponent(parts[0])] = parts.length > 1 ? decodeURIComponent(parts[1]) : '';
  });
  if (options.color) { state.color = options.color; el('color').value = options.color; }
  if (options.clip) {
    var cp = options.clip.split(':');
    state.clip = true; state.axis = { x: 0, y: 1, z: 2 }[cp[0]] || 0; state.at = Number(cp[1] || 0.5);
    state.flip = cp[2] === 'flip'; el('clip-flip').checked = state.flip;
    el('clip').checked = true; el('clip-axis').value = state.axis; el('clip-at').value = Math.round(state.at * 1000);
  }

  resize();
  var bins = drawHistogram();

  // ---- self test (#test): what the browser tests read from the status element ----
  function pixels() {
    var gl = renderer.getContext(), w = gl.drawingBufferWidth, hh = gl.drawingBufferHeight;
    var buf = new Uint8Array(4 * w * hh);
    gl.readPixels(0, 0, w, hh, gl.RGBA, gl.UNSIGNED_BYTE, buf);
    var bg = [(BACKGROUND >> 16) & 255, (BACKGROUND >> 8) & 255, BACKGROUND & 255], painted = 0, colours = new Set();
    for (var i = 0; i < buf.length; i += 4) {
      if (Math.abs(buf[i] - bg[0]) + Math.abs(buf[i + 1] - bg[1]) + Math.abs(buf[i + 2] - bg[2]) > 12) {
        painted++;
        colours.add((buf[i] >> 4) * 256 + (buf[i + 1] >> 4) * 16 + (buf[i + 2] >> 4));
      }
    }
    return { painted: painted / Math.max(1, w * hh), colours: colours.size, width: w, height: hh };
  }
  function count(array, value) {
    var c = 0;
    for (var h = 0; h < m; h++) if (array[3 * h] === value || array[3 * h + 1] === value || array[3 * h + 2] === value) c++;
    return c;
  }
  if ('test' in options) {
    setStep(0); setStatus('replay-first', visibleCount);
    setStep(1); setStatus('replay-one', visibleCount);
    setStep(Math.floor(m / 2)); setStatus('replay-half', visibleCount);
    setStep(m); setStatus('replay-last', visibleCount);
    setStatus('replay-last-text', el('step-info').textContent);
    var testSheet = m ? SH[0] : -1, testChord = m ? CH[0] : -1;
    setFilter(testSheet, -1); setStatus('sheet-shown', visibleCount); setStatus('sheet-expected', m ? count(SH, testSheet) : 0);
    setFilter(-1, testChord); setStatus('chord-shown', visibleCount); setStatus('chord-expected', m ? count(CH, testChord) : 0);
    setFilter(-1, -1);
    state.clip = true; rebuild(); setStatus('clip-shown', visibleCount); state.clip = 'clip' in options;
    ['sj', 'depth', 'layer', 'step', 'shrink', 'layers'].forEach(function (mode) { state.color = mode; rebuild(); });
    state.color = options.color || 'sheets';
    // A click at the centre of the view: the ray must hit a drawn face of a hex.
    rebuild();
    raycaster.setFromCamera(new THREE.Vector2(0, 0), camera);
    var hits = mesh ? raycaster.intersectObject(mesh) : [];
    setStatus('picked', hits.length > 0 ? triHex[hits[0].faceIndex] : -1);
    if (hits.length > 0) pick(triHex[hits[0].faceIndex]);
  }
  if (options.step !== undefined) state.step = Math.max(0, Math.min(m, Number(options.step)));
  slider.value = state.step;
  rebuild();
  var px = pixels();
  setStatus('hexes', m);
  setStatus('nodes', n);
  setStatus('sheets', distinct(SH));
  setStatus('chords', distinct(CH));
  setStatus('sheets-declared', D.sheets);
  setStatus('chords-declared', D.chords);
  setStatus('histogram-total', bins.reduce(function (a, b) { return a + b; }, 0));
  setStatus('drawn-faces', drawnFaces);
  setStatus('shown', visibleCount);
  setStatus('painted', px.painted.toFixed(4));
  setStatus('colours', px.colours);
  setStatus('canvas', px.width + 'x' + px.height);
  setStatus('load-ms', Math.round(performance.now()));
  setStatus('setup-ms', Math.round(performance.now() - t0));
  setStatus('errors', window.stcweaveErrors.join(' | '));
  setStatus('state', window.stcweaveErrors.length ? 'error' : 'ready');
  statusEl.textContent = window.stcweaveErrors.length ? 'error: ' + window.stcweaveErrors.join(' | ') :
    'ready in ' + Math.round(performance.now()) + ' ms';
})();
