// The BRDF viewer's script (specula_visual::viewer). It reads the compact tables from the
// JSON element #sv-data and draws, with canvas 2D only:
// - the lobe as two polar plots (in the plane of incidence, and across it through the
//   mirror direction) at the incident angle of a slider, linear or log, one colour per BRDF;
// - the characteristic slice theta_h x theta_d at the phi_d of a slider, one heatmap per
//   BRDF on one shared colour scale;
// - a sphere per BRDF lit by a point light the user drags, shaded from the table;
// and writes under the pointer the angles, f_r per channel and, when known, the cell's
// origin (measured, interpolated, extrapolated) and its uncertainty.
//
// A table is looked up as MERL's reference reader looks up its cells (nearest bin), then
// reduced to the compact grid (theta_d bins of 2 deg, phi_d bins of 4 deg).
//
// Self-test: opened as PAGE#selftest, the page moves its sliders and its light once drawn,
// and the pointer over the middle of each drawing, and writes into #sv-selftest, as data-*
// attributes: the script errors, the colour counts of its canvases and whether moving the
// controls changed them, how many pointer moves gave a readout of f_r (and named a cell's
// origin, and gave its uncertainty), and the time it took to become interactive (ms since navigation start); the
// browser test reads them with --dump-dom.
(function () {
  'use strict';
  const errors = [];
  window.addEventListener('error', function (e) { errors.push(String(e.message)); });
  const PI = Math.PI;
  const HALF_PI = PI / 2;
  const COLOURS = ['#d62728', '#1f77b4', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b', '#e377c2', '#17becf'];
  const ORIGINS = ['measured', 'interpolated', 'extrapolated', 'extrapolated (prior)'];
  const DECADES = 4;
  const $ = function (id) { return document.getElementById(id); };

  // ---- data ----------------------------------------------------------------------------
  function bytesOf(base64) {
    const text = atob(base64);
    const out = new Uint8Array(text.length);
    for (let i = 0; i < text.length; i++) out[i] = text.charCodeAt(i);
    return out;
  }
  // Codes to values: 0 no value (NaN), 1 zero, 2..65535 log-spaced from ln_min to ln_max.
  function dequantise(q) {
    const bytes = bytesOf(q.codes);
    const n = bytes.length >> 1;
    const out = new Float32Array(n);
    const scale = (q.ln_max - q.ln_min) / 65533;
    for (let i = 0; i < n; i++) {
      const code = bytes[2 * i] | (bytes[2 * i + 1] << 8);
      out[i] = code === 0 ? NaN : code === 1 ? 0 : Math.exp(q.ln_min + (code - 2) * scale);
    }
    return out;
  }
  const data = JSON.parse($('sv-data').textContent);
  const NH = data.theta_h_bins, ND = data.theta_d_bins, NP = data.phi_d_bins;
  const D_STRIDE = 90 / ND, P_STRIDE = 180 / NP;
  const tables = data.tables.map(function (t, i) {
    return {
      name: t.name,
      colour: COLOURS[i % COLOURS.length],
      f: dequantise(t.values),
      origins: t.origins ? bytesOf(t.origins) : null,
      uncertainty: t.uncertainty ? dequantise(t.uncertainty) : null,
    };
  });

  // ---- geometry: Rusinkiewicz's half-difference angles and MERL's bins -----------------
  function rotZ(v, a) { const c = Math.cos(a), s = Math.sin(a); return [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]; }
  function rotY(v, a) { const c = Math.cos(a), s = Math.sin(a); return [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]; }
  function norm(v) { const l = Math.hypot(v[0], v[1], v[2]); return [v[0] / l, v[1] / l, v[2] / l]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function acos(x) { return Math.acos(Math.max(-1, Math.min(1, x))); }
  function halfDiff(wi, wo) {
    const s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
    const h = dot(s, s) > 1e-24 ? norm(s) : [0, 0, 1];
    const thetaH = acos(h[2]), phiH = Math.atan2(h[1], h[0]);
    const d = rotY(rotZ(wi, -phiH), -thetaH);
    return [thetaH, acos(d[2]), Math.atan2(d[1], d[0])];
  }
  function clampBin(x, bins) { return !(x > 0) ? 0 : Math.min(Math.floor(x), bins - 1); }
  // The compact cell of half-difference angles (radians), by MERL's reader's arithmetic.
  function cellOf(hd) {
    const hDeg = Math.min(Math.max(hd[0] / HALF_PI * 90, 0), 90);
    const ih = clampBin(Math.sqrt(hDeg * 90), NH);
    const id = clampBin(hd[1] / HALF_PI * 90, 90);
    const folded = ((hd[2] % PI) + PI) % PI;
    const ip = clampBin(folded / PI * 180, 180);
    return (ih * ND + Math.floor(id / D_STRIDE)) * NP + Math.floor(ip / P_STRIDE);
  }
  // The MERL bin centre a compact cell holds, degrees [theta_h, theta_d, phi_d].
  function centreDeg(cell) {
    const ip = cell % NP, id = Math.floor(cell / NP) % ND, ih = Math.floor(cell / (NP * ND));
    return [(ih + 0.5) * (ih + 0.5) / 90, D_STRIDE * id + Math.floor(D_STRIDE / 2) + 0.5, P_STRIDE * ip + Math.floor(P_STRIDE / 2) + 0.5];
  }
  function rgbAt(t, cell) { return [t.f[3 * cell], t.f[3 * cell + 1], t.f[3 * cell + 2]]; }
  function luminance(c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
  // f_r of table t for light from wi towards wo (unit vectors, z the normal): {cell, rgb}.
  function evalAt(t, wi, wo) {
    if (wi[2] <= 0 || wo[2] <= 0) return { cell: -1, rgb: [0, 0, 0] };
    const cell = cellOf(halfDiff(wi, wo));
    return { cell: cell, rgb: rgbAt(t, cell) };
  }

  // ---- readouts ------------------------------------------------------------------------
  function num(x) { return isNaN(x) ? 'no value' : x === 0 ? '0' : Math.abs(x) >= 0.01 && Math.abs(x) < 1e4 ? x.toPrecision(4) : x.toExponential(3); }
  function cellText(t, cell) {
    if (cell < 0) return t.name + ': 0 (below the horizon)';
    const c = rgbAt(t, cell);
    let text = t.name + ': R ' + num(c[0]) + ', G ' + num(c[1]) + ', B ' + num(c[2]) + ' 1/sr';
    if (t.origins) text += ', ' + (ORIGINS[t.origins[cell]] || 'unknown origin');
    if (t.uncertainty) text += ', uncertainty ' + [0, 1, 2].map(function (k) { return num(t.uncertainty[3 * cell + k]); }).join(' / ') + ' 1/sr';
    return text;
  }
  function angleText(cell) {
    const a = centreDeg(cell);
    return 'cell at theta_h ' + a[0].toFixed(2) + ', theta_d ' + a[1].toFixed(1) + ', phi_d ' + a[2].toFixed(1) + ' deg';
  }
  function show(head, wi, wo) {
    const lines = [head];
    tables.forEach(function (t) {
      const r = evalAt(t, wi, wo);
      lines.push(cellText(t, r.cell));
      if (t === tables[0] && r.cell >= 0) lines[0] += '  (' + angleText(r.cell) + ')';
    });
    $('sv-readout').textContent = lines.join('\n');
  }
  function pointer(canvas, e) {
    const r = canvas.getBoundingClientRect();
    return [(e.clientX - r.left) * canvas.width / r.width, (e.clientY - r.top) * canvas.height / r.height];
  }
  function deg(x) { return (x * 180 / PI).toFixed(1); }

  // ---- the lobe: polar plots -----------------------------------------------------------
  const polar = $('sv-polar');
  const thetaI = $('sv-theta-i'), logScale = $('sv-log');
  const PANELS = [{ cx: 190, title: 'in the plane of incidence' }, { cx: 570, title: 'across it, through the mirror direction' }];
  const CY = 205, RADIUS = 180;
  function light() { const a = thetaI.value * PI / 180; return [Math.sin(a), 0, Math.cos(a)]; }
  // The outgoing direction at signed angle a (radians) of panel p.
  function outgoing(p, a) {
    if (p === 0) return [Math.sin(a), 0, Math.cos(a)];
    const ti = thetaI.value * PI / 180;
    const m = [-Math.sin(ti), 0, Math.cos(ti)];
    return [Math.cos(a) * m[0], Math.sin(a), Math.cos(a) * m[2]];
  }
  function drawPolar() {
    $('sv-theta-i-out').textContent = thetaI.value;
    const g = polar.getContext('2d');
    g.fillStyle = '#ffffff';
    g.fillRect(0, 0, polar.width, polar.height);
    const wi = light();
    const steps = 360;
    const curves = tables.map(function (t) {
      return PANELS.map(function (_, p) {
        const out = [];
        for (let k = 0; k <= steps; k++) {
          const a = (k / steps - 0.5) * PI * 0.995;
          out.push([a, luminance(evalAt(t, wi, outgoing(p, a)).rgb)]);
        }
        return out;
      });
    });
    let peak = 0;
    curves.forEach(function (c) { c.forEach(function (pc) { pc.forEach(function (s) { if (s[1] > peak) peak = s[1]; }); }); });
    const log = logScale.checked;
    const radius = function (v) {
      if (!(v > 0) || !(peak > 0)) return 0;
      if (!log) return RADIUS * v / peak;
      return RADIUS * Math.max(0, Math.log10(v / peak) + DECADES) / DECADES;
    };
    g.font = '12px sans-serif';
    PANELS.forEach(function (panel, p) {
      g.strokeStyle = '#d2d2d7';
      g.lineWidth = 1;
      for (let ring = 1; ring <= 4; ring++) {
        g.beginPath();
        g.arc(panel.cx, CY, RADIUS * ring / 4, PI, 2 * PI);
        g.stroke();
      }
      for (let a = -90; a <= 90; a += 30) {
        const r = a * PI / 180;
        g.beginPath();
        g.moveTo(panel.cx, CY);
        g.lineTo(panel.cx + RADIUS * Math.sin(r), CY - RADIUS * Math.cos(r));
        g.stroke();
      }
      g.fillStyle = '#3a3a3c';
      g.textAlign = 'center';
      g.fillText(panel.title, panel.cx, CY + 24);
      if (p === 0) {
        const ti = thetaI.value * PI / 180;
        g.setLineDash([5, 4]);
        g.strokeStyle = '#8e8e93';
        g.beginPath();
        g.moveTo(panel.cx, CY);
        g.lineTo(panel.cx + RADIUS * Math.sin(ti), CY - RADIUS * Math.cos(ti));
        g.stroke();
        g.setLineDash([]);
      }
      curves.forEach(function (c, i) {
        g.strokeStyle = tables[i].colour;
        g.lineWidth = 2;
        g.beginPath();
        // A cell without a value breaks the curve.
        let gap = true;
        c[p].forEach(function (s) {
          if (isNaN(s[1])) { gap = true; return; }
          const r = radius(s[1]);
          const x = panel.cx + r * Math.sin(s[0]), y = CY - r * Math.cos(s[0]);
          if (gap) g.moveTo(x, y); else g.lineTo(x, y);
          gap = false;
        });
        g.stroke();
      });
    });
    g.fillStyle = '#3a3a3c';
    g.textAlign = 'left';
    const scale = log ? 'rings: decades below the peak ' + num(peak) + ' 1/sr' : 'outer ring: ' + num(peak) + ' 1/sr';
    g.fillText(scale, 8, 16);
  }
  polar.addEventListener('mousemove', function (e) {
    const xy = pointer(polar, e);
    const p = xy[0] < polar.width / 2 ? 0 : 1;
    const a = Math.atan2(xy[0] - PANELS[p].cx, CY - xy[1]);
    if (Math.abs(a) > HALF_PI) return;
    const wi = light(), wo = outgoing(p, a);
    const head = p === 0
      ? 'plane of incidence: theta_i ' + thetaI.value + ' deg, camera at ' + deg(a) + ' deg (negative: the mirror side)'
      : 'across the plane of incidence: theta_i ' + thetaI.value + ' deg, camera ' + deg(a) + ' deg from the mirror direction';
    show(head, wi, wo);
  });

  // ---- the characteristic slice: heatmaps ------------------------------------------------
  const phiD = $('sv-phi-d');
  const CELL_W = 3, CELL_H = 6;
  // One colour scale for every table: log10 luminance over all their cells, from the 2nd
  // percentile (at most 10 decades below the top) to the largest.
  const range = (function () {
    const logs = [];
    tables.forEach(function (t) {
      for (let c = 0; c < NH * ND * NP; c++) {
        const l = luminance(rgbAt(t, c));
        if (l > 0) logs.push(Math.log10(l));
      }
    });
    if (logs.length === 0) return [0, 1];
    const sorted = Float64Array.from(logs).sort();
    const hi = sorted[sorted.length - 1];
    const lo = Math.max(sorted[Math.floor(0.02 * (sorted.length - 1))], hi - 10);
    return hi > lo ? [lo, hi] : [hi - 1, hi];
  })();
  const STOPS = [[0, 0, 4], [40, 11, 84], [101, 21, 110], [159, 42, 99], [212, 72, 66], [245, 125, 21], [250, 193, 39], [252, 255, 164]];
  function colourOf(v) {
    if (isNaN(v)) return [200, 200, 200];
    const t = v > 0 ? Math.max(0, Math.min(1, (Math.log10(v) - range[0]) / (range[1] - range[0]))) : 0;
    const x = t * (STOPS.length - 1), k = Math.min(Math.floor(x), STOPS.length - 2), f = x - k;
    return [0, 1, 2].map(function (c) { return Math.round(STOPS[k][c] + f * (STOPS[k + 1][c] - STOPS[k][c])); });
  }
  const slices = tables.map(function (t) {
    const fig = document.createElement('figure');
    const canvas = document.createElement('canvas');
    canvas.width = NH * CELL_W;
    canvas.height = ND * CELL_H;
    const caption = document.createElement('figcaption');
    caption.textContent = t.name;
    fig.appendChild(canvas);
    fig.appendChild(caption);
    $('sv-slices').appendChild(fig);
    canvas.addEventListener('mousemove', function (e) {
      const xy = pointer(canvas, e);
      const ih = Math.min(NH - 1, Math.max(0, Math.floor(xy[0] / CELL_W)));
      const id = Math.min(ND - 1, Math.max(0, ND - 1 - Math.floor(xy[1] / CELL_H)));
      const cell = (ih * ND + id) * NP + Number(phiD.value);
      $('sv-readout').textContent = ['characteristic slice: ' + angleText(cell)]
        .concat(tables.map(function (u) { return cellText(u, cell); })).join('\n');
    });
    return canvas;
  });
  function drawSlices() {
    const ip = Number(phiD.value);
    $('sv-phi-d-out').textContent = centreDeg(ip)[2].toFixed(1);
    tables.forEach(function (t, i) {
      const canvas = slices[i], g = canvas.getContext('2d');
      const image = g.createImageData(canvas.width, canvas.height);
      for (let y = 0; y < canvas.height; y++) {
        const id = ND - 1 - Math.floor(y / CELL_H);
        for (let x = 0; x < canvas.width; x++) {
          const cell = (Math.floor(x / CELL_W) * ND + id) * NP + ip;
          const c = colourOf(luminance(rgbAt(t, cell)));
          const o = 4 * (y * canvas.width + x);
          image.data[o] = c[0]; image.data[o + 1] = c[1]; image.data[o + 2] = c[2]; image.data[o + 3] = 255;
        }
      }
      g.putImageData(image, 0, 0);
      g.fillStyle = '#ffffff';
      g.font = '11px sans-serif';
      g.fillText('theta_h (sqrt axis) \u2192', 4, canvas.height - 4);
      g.save();
      g.translate(12, canvas.height - 110);
      g.rotate(-HALF_PI);
      g.fillText('theta_d \u2192', 0, 0);
      g.restore();
    });
  }
  function drawColourbar() {
    const bar = $('sv-colourbar'), g = bar.getContext('2d');
    g.fillStyle = '#ffffff';
    g.fillRect(0, 0, bar.width, bar.height);
    const w = bar.width - 40;
    for (let x = 0; x < w; x++) {
      const c = colourOf(Math.pow(10, range[0] + (range[1] - range[0]) * x / (w - 1)));
      g.fillStyle = 'rgb(' + c.join(',') + ')';
      g.fillRect(20 + x, 4, 1, 18);
    }
    g.fillStyle = '#3a3a3c';
    g.font = '11px sans-serif';
    g.textAlign = 'center';
    for (let k = Math.ceil(range[0]); k <= Math.floor(range[1]); k++) {
      g.fillText('1e' + k, 20 + w * (k - range[0]) / (range[1] - range[0]), 38);
    }
  }

  // ---- the lit sphere --------------------------------------------------------------------
  const SIZE = 200;
  const exposure = $('sv-exposure');
  let lightDir = norm([0.5, 0.45, 0.74]);
  function frame(n) {
    const a = Math.abs(n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    const t = norm(cross(a, n));
    return [t, cross(n, t)];
  }
  function local(v, n, tb) { return [dot(v, tb[0]), dot(v, tb[1]), dot(v, n)]; }
  // The sphere's normal under canvas pixel (x, y), or null off the sphere.
  function normalAt(x, y) {
    const u = (x + 0.5) / SIZE * 2 - 1, v = 1 - (y + 0.5) / SIZE * 2;
    const r2 = u * u + v * v;
    return r2 >= 1 ? null : [u, v, Math.sqrt(1 - r2)];
  }
  const VIEW = [0, 0, 1];
  function srgb(x) { const c = Math.max(0, Math.min(1, x)); return Math.round(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055)); }
  const spheres = tables.map(function (t) {
    const fig = document.createElement('figure');
    const canvas = document.createElement('canvas');
    canvas.width = SIZE;
    canvas.height = SIZE;
    const caption = document.createElement('figcaption');
    caption.textContent = t.name;
    fig.appendChild(canvas);
    fig.appendChild(caption);
    $('sv-spheres').appendChild(fig);
    let dragging = false;
    const drag = function (e) {
      const xy = pointer(canvas, e);
      const u = xy[0] / SIZE * 2 - 1, v = 1 - xy[1] / SIZE * 2;
      const r2 = u * u + v * v;
      lightDir = r2 < 0.995 ? [u, v, Math.sqrt(1 - r2)] : norm([u, v, 0.07]);
      drawSpheres();
    };
    canvas.addEventListener('pointerdown', function (e) { dragging = true; canvas.setPointerCapture(e.pointerId); drag(e); });
    canvas.addEventListener('pointerup', function () { dragging = false; });
    canvas.addEventListener('pointermove', function (e) {
      if (dragging) drag(e);
      const xy = pointer(canvas, e);
      const n = normalAt(Math.floor(xy[0]), Math.floor(xy[1]));
      if (!n) return;
      const tb = frame(n);
      const wi = local(lightDir, n, tb), wo = local(VIEW, n, tb);
      show('sphere: light at ' + deg(acos(wi[2])) + ' deg, camera at ' + deg(acos(wo[2])) + ' deg from the normal', wi, wo);
    });
    return canvas;
  });
  function drawSpheres() {
    $('sv-exposure-out').textContent = exposure.value;
    const gain = PI * Math.pow(2, Number(exposure.value));
    tables.forEach(function (t, i) {
      const canvas = spheres[i], g = canvas.getContext('2d');
      const image = g.createImageData(SIZE, SIZE);
      for (let y = 0; y < SIZE; y++) {
        for (let x = 0; x < SIZE; x++) {
          const o = 4 * (y * SIZE + x);
          const n = normalAt(x, y);
          let c = [0.06, 0.06, 0.07];
          if (n) {
            const cos = dot(n, lightDir);
            c = [0, 0, 0];
            if (cos > 0) {
              const tb = frame(n);
              const f = evalAt(t, local(lightDir, n, tb), local(VIEW, n, tb)).rgb;
              c = f.map(function (v) { return isNaN(v) ? 0.5 : 1 - Math.exp(-v * cos * gain); });
            }
          }
          image.data[o] = srgb(c[0]); image.data[o + 1] = srgb(c[1]); image.data[o + 2] = srgb(c[2]); image.data[o + 3] = 255;
        }
      }
      g.putImageData(image, 0, 0);
    });
  }

  // ---- legend, wiring, self-test ----------------------------------------------------------
  tables.forEach(function (t) {
    const item = document.createElement('span');
    const swatch = document.createElement('i');
    swatch.style.background = t.colour;
    item.appendChild(swatch);
    item.appendChild(document.createTextNode(t.name));
    $('sv-legend').appendChild(item);
  });
  thetaI.addEventListener('input', drawPolar);
  logScale.addEventListener('change', drawPolar);
  phiD.addEventListener('input', drawSlices);
  exposure.addEventListener('input', drawSpheres);

  // FNV-1a hash and number of distinct colours of a canvas's pixels.
  function fingerprint(canvas) {
    const d = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    let hash = 0x811c9dc5;
    const colours = new Set();
    for (let i = 0; i < d.length; i += 4) {
      colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      for (let k = 0; k < 3; k++) hash = Math.imul(hash ^ d[i + k], 16777619) >>> 0;
    }
    return { hash: hash, colours: colours.size };
  }
  function selfTest(readyMs) {
    const out = $('sv-selftest');
    const canvases = { polar: polar, slice: slices[0], sphere: spheres[0] };
    const before = {};
    Object.keys(canvases).forEach(function (k) { before[k] = fingerprint(canvases[k]); });
    thetaI.value = Number(thetaI.value) === 60 ? 20 : 60;
    thetaI.dispatchEvent(new Event('input'));
    phiD.value = 5;
    phiD.dispatchEvent(new Event('input'));
    lightDir = norm([-0.6, -0.2, 0.77]);
    drawSpheres();
    Object.keys(canvases).forEach(function (k) {
      const after = fingerprint(canvases[k]);
      out.setAttribute('data-' + k + '-colours', before[k].colours);
      out.setAttribute('data-' + k + '-changed', before[k].hash !== after.hash ? 1 : 0);
    });
    // The pointer at the middle of each drawing: a readout of f_r each time.
    let readouts = 0, origins = 0, uncertainties = 0;
    [[polar, 'mousemove'], [slices[0], 'mousemove'], [spheres[0], 'pointermove']].forEach(function (pair) {
      const r = pair[0].getBoundingClientRect();
      $('sv-readout').textContent = '';
      pair[0].dispatchEvent(new PointerEvent(pair[1], { clientX: r.left + r.width / 2, clientY: r.top + r.height / 2 }));
      const text = $('sv-readout').textContent;
      if (text.indexOf('1/sr') >= 0) readouts++;
      if (/measured|interpolated|extrapolated/.test(text)) origins++;
      if (text.indexOf('uncertainty') >= 0) uncertainties++;
    });
    out.setAttribute('data-readouts', readouts);
    out.setAttribute('data-readout-origins', origins);
    out.setAttribute('data-readout-uncertainties', uncertainties);
    out.setAttribute('data-ready-ms', Math.round(readyMs));
    out.setAttribute('data-tables', tables.length);
    out.setAttribute('data-errors', errors.length);
    out.textContent = errors.join('\n');
  }

  try {
    drawPolar();
    drawSlices();
    drawColourbar();
    drawSpheres();
  } catch (e) {
    errors.push(String(e));
  }
  const readyMs = performance.now();
  if (location.hash === '#selftest') {
    try { selfTest(readyMs); } catch (e) { errors.push(String(e)); $('sv-selftest').setAttribute('data-errors', errors.length); $('sv-selftest').textContent = errors.join('\n'); }
  }
})();
