// clapper's animation player: bells and clappers drawn on a canvas from
// their figures (metres, the bell's frame), each moment showing the last
// frame at or before it, the synthesised sound playing in step, with slow
// motion, a time slider and a cursor on theta and phi against time. Used by
// `clapper animate --out FILE.html` and by the web app's stroke view.
//
//   ClapperPlayer.mount(element, data, audioUrl)  ->  player
//
// `data` is what `player_json` writes. The player keeps, on `element`,
// data-t (s), data-theta and data-phi (deg, the first bell as drawn),
// data-strikes-shown (strikes flashed since the page loaded), data-draws
// (pictures drawn) and data-bells (bells drawn), for tests.
(function (global) {
  "use strict";
  const FLASH = 0.08; // s of the viewer's time a strike's flash stays
  const COLOURS = ["#1f6fb4", "#c2410c", "#2f9e44", "#7048e8", "#e8590c", "#0c8599", "#a61e4d", "#5c940d"];

  // Index of the last element of sorted `ts` at or before `t` (0 if none).
  function lastAtOrBefore(ts, t) {
    let lo = 0, hi = ts.length - 1;
    if (t >= ts[hi]) return hi;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (ts[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  }

  function path(shape) {
    const p = new Path2D();
    if (shape.kind === "circle") {
      p.arc(shape.centre[0], shape.centre[1], shape.radius, 0, 2 * Math.PI);
    } else {
      shape.points.forEach((q, i) => (i ? p.lineTo(q[0], q[1]) : p.moveTo(q[0], q[1])));
      if (shape.kind === "polygon") p.closePath();
    }
    return p;
  }

  function parts(list) {
    return list.map((part) => ({ path: path(part), fill: part.fill, stroke: part.stroke, width: part.width, dashed: part.dashed }));
  }

  function paint(g, list) {
    for (const p of list) {
      if (p.fill) { g.fillStyle = p.fill; g.fill(p.path); }
      if (p.stroke) {
        g.strokeStyle = p.stroke; g.lineWidth = p.width;
        g.setLineDash(p.dashed ? [4 * p.width, 3 * p.width] : []);
        g.stroke(p.path);
      }
    }
    g.setLineDash([]);
  }

  // A caption that fits `width` px: one line at 12 px, or down to 10 px;
  // else two lines (the name, then how it rings) as large as fit; a line
  // still too long is cut with an ellipsis.
  function fitCaption(text, width) {
    const g = document.createElement("canvas").getContext("2d");
    const wide = (t, px) => { g.font = `${px}px sans-serif`; return g.measureText(t).width; };
    for (const px of [12, 11, 10]) if (wide(text, px) <= width) return { px, lines: [text] };
    const cut = text.indexOf(": ");
    const lines = cut > 0 ? [text.slice(0, cut + 1), text.slice(cut + 2)] : [text];
    let px = 12;
    while (px > 9 && lines.some((l) => wide(l, px) > width)) px -= 1;
    return {
      px,
      lines: lines.map((l) => {
        if (wide(l, px) <= width) return l;
        while (l.length > 1 && wide(l + "…", px) > width) l = l.slice(0, -1);
        return l + "…";
      }),
    };
  }

  class ClapperPlayer {
    constructor(root, data, audioUrl) {
      this.root = root;
      this.data = data;
      this.duration = data.duration_s;
      this.bells = data.bells.map((b) => ({
        name: b.name, caption: b.caption, figure: b.figure,
        bell: parts(b.figure.bell), clapper: parts(b.figure.clapper),
        ts: Float64Array.from(b.t_s),
        theta: Float64Array.from(b.theta_deg, (d) => (d * Math.PI) / 180),
        phi: Float64Array.from(b.phi_deg, (d) => (d * Math.PI) / 180),
        strikes: b.strikes,
      }));
      root.classList.add("clapper-player");
      root.innerHTML = `
        <canvas class="cp-bells"></canvas>
        <div class="cp-controls">
          <button type="button" class="cp-play">▶ Play</button>
          <label>speed <select class="cp-speed"><option value="1">1</option><option value="0.25">1/4</option><option value="0.1">1/10</option></select></label>
          <input class="cp-time" type="range" min="0" max="1000" value="0" aria-label="time">
          <span class="cp-readout"></span>
        </div>
        <canvas class="cp-plot"></canvas>
        ${data.rounds_interval_s ? '<canvas class="cp-diagram"></canvas>' : ""}`;
      this.canvas = root.querySelector(".cp-bells");
      this.plot = root.querySelector(".cp-plot");
      this.diagram = root.querySelector(".cp-diagram");
      this.button = root.querySelector(".cp-play");
      this.speedBox = root.querySelector(".cp-speed");
      this.slider = root.querySelector(".cp-time");
      this.readout = root.querySelector(".cp-readout");
      this.audio = audioUrl ? new Audio(audioUrl) : null;
      this.audioOk = !!this.audio;
      this.speed = 1;
      this.t = 0;
      this.playing = false;
      this.flashed = new Set();
      root.dataset.strikesShown = "0";
      root.dataset.bells = String(this.bells.length);
      this.button.addEventListener("click", () => (this.playing ? this.pause() : this.play()));
      this.speedBox.addEventListener("change", () => this.setSpeed(Number(this.speedBox.value)));
      this.slider.addEventListener("input", () => this.seek((Number(this.slider.value) / 1000) * this.duration));
      this.tick = this.tick.bind(this);
      this.resize();
      this.draw(0);
    }

    static mount(root, data, audioUrl) {
      return new ClapperPlayer(root, data, audioUrl);
    }

    resize() {
      const w = Math.max(320, Math.min(this.root.clientWidth || 640, 960));
      const n = this.bells.length;
      const ratio = window.devicePixelRatio || 1;
      const size = (c, h) => { c.width = Math.round(w * ratio); c.height = Math.round(h * ratio); c.style.width = w + "px"; c.style.height = h + "px"; };
      // The bells' layout, as the SVG and GIF lay them out: one row up to
      // four bells, else two; one scale for all. Each caption fits its
      // cell (never over its neighbour's): smaller, else on two lines, for
      // which one or two bells keep a deeper band.
      const cols = n > 4 ? Math.ceil(n / 2) : n, rows = Math.ceil(n / cols);
      const font = 13, top = 6, band = (n > 2 ? 1.6 : 2.7) * font;
      const cell = w / cols;
      this.captionLines = this.bells.map((b) => fitCaption(n > 2 ? b.name : `${b.name}: ${b.caption}`, cell - 10));
      const rowHeight = n === 1 ? Math.min(w, 440) : Math.min(440, cell * 1.05 + band);
      const bellsHeight = top + rows * rowHeight + 4;
      size(this.canvas, bellsHeight);
      size(this.plot, 164);
      if (this.diagram) size(this.diagram, 24 * n + 40);
      this.ratio = ratio;
      const area = rowHeight - band;
      this.scale = Math.min(...this.bells.map((b) => (0.48 * Math.min(cell, area)) / b.figure.reach));
      this.centres = this.bells.map((_, i) => [cell * ((i % cols) + 0.5), top + Math.floor(i / cols) * rowHeight + area / 2]);
      this.captions = this.bells.map((_, i) => [cell * ((i % cols) + 0.5), top + (Math.floor(i / cols) + 1) * rowHeight - 0.5 * font]);
      this.root.dataset.captions = JSON.stringify(this.captionLines);
      this.renderPlot();
      if (this.diagram) this.renderDiagram();
    }

    // A picture drawn once, the size of `target`, white, in CSS px: its
    // context, size and plotting area (`margins` left, top, right, bottom).
    offscreen(target, margins) {
      const c = document.createElement("canvas");
      c.width = target.width; c.height = target.height;
      const g = c.getContext("2d");
      g.scale(this.ratio, this.ratio);
      const w = c.width / this.ratio, h = c.height / this.ratio;
      const [l, t, r, b] = margins;
      g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
      g.font = "11px sans-serif";
      return { c, g, a: { x: l, y: t, w: w - l - r, h: h - t - b } };
    }

    // Theta and phi against time, drawn once; each moment adds the cursor.
    renderPlot() {
      const { c, g, a } = this.offscreen(this.plot, [44, 8, 12, 22]);
      this.plotArea = a;
      g.strokeStyle = "#ccc"; g.lineWidth = 1; g.fillStyle = "#333";
      for (const d of [-180, -90, 0, 90, 180]) {
        const y = a.y + a.h * (1 - (d + 180) / 360);
        g.beginPath(); g.moveTo(a.x, y); g.lineTo(a.x + a.w, y); g.stroke();
        g.fillText(String(d), 8, y + 4);
      }
      g.fillText("deg", 8, a.y + a.h + 18);
      g.fillText(`time (s), 0 to ${this.duration.toFixed(2)}: θ solid, φ dashed`, a.x, a.y + a.h + 18);
      this.bells.forEach((b, k) => {
        for (const [series, dash] of [[b.theta, []], [b.phi, [4, 3]]]) {
          g.strokeStyle = COLOURS[k % COLOURS.length]; g.setLineDash(dash); g.lineWidth = 1.4;
          g.beginPath();
          for (let i = 0; i < b.ts.length; i++) {
            const x = a.x + (a.w * b.ts[i]) / this.duration;
            const y = a.y + a.h * (1 - ((series[i] * 180) / Math.PI + 180) / 360);
            i ? g.lineTo(x, y) : g.moveTo(x, y);
          }
          g.stroke();
        }
        g.setLineDash([]);
      });
      g.strokeStyle = "#333"; g.strokeRect(a.x, a.y, a.w, a.h);
      this.plotImage = c;
    }

    // Rounds: one lane a bell, each blow against its ideal place.
    renderDiagram() {
      const { c, g, a } = this.offscreen(this.diagram, [80, 8, 12, 24]);
      this.diagramArea = a;
      const lane = a.h / this.bells.length;
      this.bells.forEach((b, i) => {
        const y = a.y + lane * (i + 0.5);
        g.fillStyle = "#333"; g.fillText(b.name.slice(0, 12), 4, y + 4);
        g.strokeStyle = "#eee"; g.beginPath(); g.moveTo(a.x, y); g.lineTo(a.x + a.w, y); g.stroke();
        for (const s of b.strikes) {
          const x = a.x + (a.w * s.t_s) / this.duration;
          if (s.first && s.ideal_s != null) {
            const xi = a.x + (a.w * s.ideal_s) / this.duration;
            g.strokeStyle = "#999"; g.strokeRect(xi - 3, y - 6, 6, 12);
          }
          g.fillStyle = s.first ? (s.side === "hand" ? "#1f6fb4" : "#c2410c") : "#9a9a9a";
          g.beginPath(); g.arc(x, y, s.first ? 4 : 2.5, 0, 2 * Math.PI); g.fill();
        }
      });
      g.fillStyle = "#333";
      g.fillText("blows (handstroke blue, backstroke orange; the clapper's later impacts small, grey) against their places (boxes)", a.x, a.y + a.h + 20);
      this.diagramImage = c;
    }

    // A picture drawn once, copied to `canvas` with a line at time `t`.
    cursor(canvas, image, a, t) {
      const h = canvas.getContext("2d");
      h.setTransform(1, 0, 0, 1, 0, 0);
      h.drawImage(image, 0, 0);
      h.setTransform(this.ratio, 0, 0, this.ratio, 0, 0);
      const x = a.x + (a.w * t) / this.duration;
      h.strokeStyle = "#d9480f"; h.lineWidth = 1.5;
      h.beginPath(); h.moveTo(x, a.y); h.lineTo(x, a.y + a.h); h.stroke();
    }

    setSpeed(v) {
      this.t = this.now();
      this.speed = v;
      this.wall0 = performance.now(); this.t0 = this.t;
      if (this.audio) { this.audio.playbackRate = v; }
    }

    seek(t) {
      this.t = Math.max(0, Math.min(this.duration, t));
      this.wall0 = performance.now(); this.t0 = this.t;
      if (this.audio) { try { this.audio.currentTime = this.t; } catch (e) { /* not loaded yet */ } }
      if (!this.playing) this.draw(this.t);
    }

    now() {
      if (!this.playing) return this.t;
      if (this.audio && this.audioOk && !this.audio.paused && this.audio.currentTime > 0) return this.audio.currentTime;
      return this.t0 + ((performance.now() - this.wall0) / 1000) * this.speed;
    }

    play() {
      if (this.t >= this.duration) { this.t = 0; this.flashed.clear(); }
      this.wall0 = performance.now(); this.t0 = this.t;
      this.playing = true;
      this.button.textContent = "❚❚ Pause";
      if (this.audio) {
        this.audio.playbackRate = this.speed;
        try { this.audio.currentTime = this.t; } catch (e) { /* not loaded yet */ }
        const p = this.audio.play();
        if (p && p.catch) p.catch(() => { this.audioOk = false; });
      }
      requestAnimationFrame(this.tick);
    }

    pause() {
      this.t = this.now();
      this.playing = false;
      this.button.textContent = "▶ Play";
      if (this.audio) this.audio.pause();
      this.draw(this.t);
    }

    tick() {
      if (!this.playing) return;
      this.t = this.now();
      if (this.t >= this.duration) {
        this.t = this.duration;
        this.pause();
        return;
      }
      this.draw(this.t);
      requestAnimationFrame(this.tick);
    }

    draw(t) {
      const g = this.canvas.getContext("2d");
      const r = this.ratio;
      g.setTransform(r, 0, 0, r, 0, 0);
      g.fillStyle = "#fff";
      g.fillRect(0, 0, this.canvas.width / r, this.canvas.height / r);
      const span = FLASH * this.speed;
      this.bells.forEach((b, k) => {
        const i = lastAtOrBefore(b.ts, t);
        const theta = b.theta[i], phi = b.phi[i];
        const [cx, cy] = this.centres[k];
        const s = this.scale, f = b.figure;
        g.setTransform(r * s, 0, 0, -r * s, r * cx, r * cy);
        g.strokeStyle = "#8c8c8c"; g.lineWidth = 0.004 * f.diameter; g.setLineDash([0.03 * f.diameter, 0.02 * f.diameter]);
        g.beginPath(); g.moveTo(0, 0); g.lineTo(0, -f.reach); g.stroke(); g.setLineDash([]);
        g.rotate(theta);
        paint(g, b.bell);
        g.save();
        g.translate(f.clapper_pivot[0], f.clapper_pivot[1]);
        g.rotate(phi);
        paint(g, b.clapper);
        g.restore();
        for (let j = 0; j < b.strikes.length; j++) {
          const st = b.strikes[j];
          const age = t - st.t_s;
          if (age < 0 || age >= span) continue;
          const p = f.strike_points[st.side === "back" ? 1 : 0];
          g.fillStyle = "#ffcc00"; g.strokeStyle = "#d9480f"; g.lineWidth = 0.01 * f.diameter;
          g.beginPath(); g.arc(p[0], p[1], (st.first ? 0.07 : 0.045) * f.diameter, 0, 2 * Math.PI); g.fill(); g.stroke();
          const key = k * 100000 + j;
          if (!this.flashed.has(key)) { this.flashed.add(key); this.root.dataset.strikesShown = String(this.flashed.size); }
        }
        g.setTransform(r, 0, 0, r, 0, 0);
        g.fillStyle = "#222"; g.textAlign = "center";
        const cap = this.captions[k], fit = this.captionLines[k];
        g.font = `${fit.px}px sans-serif`;
        fit.lines.forEach((line, j) => g.fillText(line, cap[0], cap[1] - (fit.lines.length - 1 - j) * (fit.px + 2)));
        g.textAlign = "start";
        if (k === 0) {
          this.root.dataset.theta = String((theta * 180) / Math.PI);
          this.root.dataset.phi = String((phi * 180) / Math.PI);
        }
      });
      this.root.dataset.t = String(t);
      this.draws = (this.draws || 0) + 1;
      this.root.dataset.draws = String(this.draws);
      this.cursor(this.plot, this.plotImage, this.plotArea, t);
      if (this.diagram) this.cursor(this.diagram, this.diagramImage, this.diagramArea, t);
      this.slider.value = String(Math.round((1000 * t) / this.duration));
      this.readout.textContent = `${t.toFixed(3)} s of ${this.duration.toFixed(2)} s`;
    }
  }

  global.ClapperPlayer = ClapperPlayer;
})(typeof window !== "undefined" ? window : globalThis);
