/* trustcbr console: the participant's page script (served as /assets/app.js).
 *
 * At "/" it shows the study's consent text and Start (and Resume when this browser holds a
 * token). At "/p/{token}" it renders everything from the server's STATE alone: GET /api/session
 * on load, and every POST reply is a STATE too, so a reload resumes where the server is.
 * Phases: "watch" (the run is animated on a canvas; Interrupt or the space bar stops it),
 * "state-cause" (why it was stopped), "rate" (the trust question) and "done".
 * Untrusted text is only ever set with textContent. No libraries, no build step.
 */
"use strict";

(function () {
  const TOKEN_KEY = "trustcbr-console-token";
  const $ = (id) => document.getElementById(id);

  const main = $("main");
  const canvas = $("map");
  const interruptBtn = $("interrupt");

  let token = null;   // the participant token (only at /p/{token})
  let scene = null;   // GET /api/scene, fetched once
  let state = null;   // the last STATE received
  let anim = null;    // the run on screen: see newAnim()
  let busy = false;   // a statement or rating is being sent
  let shownLast = ""; // which STATE.last the explanation region shows
  let shownRating = null; // which rating number the rate form was built for

  // ---------------------------------------------------------------- small helpers

  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function storeGet() {
    try { return localStorage.getItem(TOKEN_KEY); } catch (e) { return null; }
  }

  function storeSet(v) {
    try { localStorage.setItem(TOKEN_KEY, v); } catch (e) { /* private mode: no resume */ }
  }

  const fmt = (t) => (Math.round(t * 10) / 10).toFixed(1);
  const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));

  function setPhase(p) {
    main.setAttribute("data-phase", p);
  }

  // ---------------------------------------------------------------- networking

  /** Shows the error with a Retry button; resolves when Retry is pressed. */
  function waitForRetry(message, status) {
    return new Promise((resolve) => {
      const box = $("alert");
      box.textContent = "";
      box.appendChild(el("p", {}, message));
      const retry = el("button", { type: "button", id: "retry" }, "Retry");
      box.appendChild(retry);
      if (status === 401 || status === 403 || status === 404) {
        const p = el("p");
        p.appendChild(el("a", { href: "/" }, "Back to the start page"));
        box.appendChild(p);
      }
      retry.addEventListener("click", () => { box.textContent = ""; resolve(); }, { once: true });
      retry.focus();
    });
  }

  /** Sends one request and returns its JSON. A request the session refuses (409) is answered
   *  with the session's state instead; on any other failure it shows an alert with Retry and
   *  repeats the same request when asked (repeats are harmless server-side), so it never rejects. */
  async function api(method, path, body) {
    for (;;) {
      let message;
      let status = 0;
      try {
        const headers = {};
        if (token) headers["Authorization"] = "Bearer " + token;
        if (body !== undefined) headers["Content-Type"] = "application/json";
        const res = await fetch(path, {
          method,
          headers,
          body: body === undefined ? undefined : JSON.stringify(body),
          cache: "no-store",
        });
        status = res.status;
        const text = await res.text();
        let data = null;
        try { data = text ? JSON.parse(text) : null; } catch (e) { data = null; }
        if (res.ok) return data;
        if (status === 409 && token && path !== "/api/session") {
          // The request no longer fits the session (another tab moved it on, a key press
          // that came too late): take the session up where the server has it. Every POST
          // answers with the state, so the caller renders this one alike.
          return api("GET", "/api/session");
        }
        const why = data && typeof data.error === "string" ? data.error : "HTTP " + res.status;
        message = "The server refused the request: " + why + ".";
      } catch (e) {
        message = "The connection to the study server failed. Check your network and retry.";
      }
      await waitForRetry(message, status);
    }
  }

  // ---------------------------------------------------------------- start page

  async function showConsent() {
    setPhase("consent");
    const study = await api("GET", "/api/study");
    setTitle(study);
    const box = $("consent-text");
    box.textContent = "";
    for (const para of String(study.consent || "").split(/\r?\n[ \t]*\r?\n/)) {
      if (para.trim()) box.appendChild(el("p", {}, para.trim()));
    }
    if (study.minutes) {
      box.appendChild(el("p", { class: "note" }, "It takes about " + study.minutes + " minutes."));
    }
    const stored = storeGet();
    $("resume").hidden = !stored;
    $("resume-note").hidden = !stored;
    $("loading").hidden = true;
    $("consent-view").hidden = false;
  }

  function setTitle(study) {
    if (study && study.title) {
      $("title").textContent = study.title;
      document.title = study.title;
    }
  }

  $("start").addEventListener("click", async () => {
    const btn = $("start");
    if (btn.disabled) return;
    btn.disabled = true;
    const r = await api("POST", "/api/participants", { consent: true });
    token = r.token;
    storeSet(token);
    history.replaceState(null, "", "/p/" + encodeURIComponent(token));
    $("consent-view").hidden = true;
    startSession();
  });

  $("resume").addEventListener("click", () => {
    const stored = storeGet();
    if (stored) location.assign("/p/" + encodeURIComponent(stored));
  });

  // ---------------------------------------------------------------- the session

  async function startSession() {
    $("loading").hidden = false;
    // The title is decoration: fetch it without the retry machinery.
    fetch("/api/study").then((r) => (r.ok ? r.json() : null)).then(setTitle).catch(() => {});
    const s = await api("GET", "/api/session");
    $("loading").hidden = true;
    $("session-view").hidden = false;
    render(s);
  }

  /** Shows STATE `s`: the single entry point after every reply. */
  function render(s) {
    state = s;
    setPhase(s.phase);
    renderProgress(s.progress);
    renderLast(s);
    const phase = s.phase;
    $("run-view").hidden = !(phase === "watch" || phase === "state-cause");
    $("rate-view").hidden = phase !== "rate";
    $("done-view").hidden = phase !== "done";
    if (phase !== "watch" && phase !== "state-cause") dropAnim();
    if (phase !== "rate") shownRating = null;
    if (phase === "watch") enterWatch(s);
    else if (phase === "state-cause") enterCause(s);
    else if (phase === "rate") enterRate(s);
    else if (phase === "done") $("done").focus();
  }

  function renderProgress(p) {
    if (!p) return;
    $("progress").textContent =
      "Commands: " + p.commands + " of " + p.max_commands +
      " · Behaviors: " + p.behaviors + " of " + p.max_behaviors;
  }

  const DECISIONS = {
    keep: "The robot keeps its behavior",
    switch: "The robot changes its behavior",
    settled: "The robot settled on this behavior",
    abandoned: "The robot gave up looking for a better behavior",
  };

  /** The explanation of the last closed command, when the condition gives one. Hidden while
   *  the participant states a cause (it is about an earlier command then). */
  function renderLast(s) {
    const box = $("explanation");
    const last = s.last;
    if (!last || last.explanation == null || s.phase === "state-cause") {
      box.textContent = "";
      shownLast = "";
      return;
    }
    const key = last.command + "/" + last.decision + "/" + last.explanation;
    if (key === shownLast) return; // unchanged: do not announce it again
    shownLast = key;
    box.textContent = "";
    box.appendChild(el("h2", {}, "Why the robot changed"));
    box.appendChild(el("p", { class: "decision" }, DECISIONS[last.decision] || last.decision));
    box.appendChild(el("p", {}, last.explanation));
  }

  // ---------------------------------------------------------------- watch

  function newAnim(cmd) {
    return {
      index: cmd.index,
      run: cmd.run,
      speedup: cmd.speedup > 0 ? cmd.speedup : 1,
      startMs: null,   // performance.now() when the animation started
      frozenAt: null,  // run time where it stopped (interrupt, end, or stopped_at)
      closing: false,  // a stop or end was sent for this command: never send the other
      logged: 0,       // how many events (in time order) are in the log
      events: (cmd.run.events || []).slice().sort((a, b) => a.t - b.t),
      raf: 0,
    };
  }

  function dropAnim() {
    if (anim && anim.raf) cancelAnimationFrame(anim.raf);
    anim = null;
  }

  function showRunHeader(cmd) {
    $("behavior").textContent = "Behavior: " + cmd.behavior;
    $("event-log").textContent = "";
  }

  async function enterWatch(s) {
    const cmd = s.command;
    if (anim && anim.index === cmd.index) return; // this run is already on screen
    dropAnim();
    const a = (anim = newAnim(cmd));
    showRunHeader(cmd);
    $("cause-form").hidden = true;
    interruptBtn.hidden = false;
    interruptBtn.disabled = true;
    $("interrupt-hint").hidden = false;
    setClock(a, 0);
    await ensureScene();
    if (anim !== a) return;
    layoutCanvas();
    drawFrame(a, 0);
    const reply = await api("POST", "/api/shown", { command: a.index });
    if (anim !== a) return;
    if (reply.phase !== "watch" || !reply.command || reply.command.index !== a.index) {
      render(reply);
      return;
    }
    state = reply;
    renderProgress(reply.progress);
    a.startMs = performance.now();
    interruptBtn.disabled = false;
    interruptBtn.focus();
    a.raf = requestAnimationFrame(tick);
  }

  const runTime = (a) => ((performance.now() - a.startMs) / 1000) * a.speedup;

  function tick() {
    const a = anim;
    if (!a || a.startMs === null || a.frozenAt !== null) return;
    const dur = a.run.duration_s;
    const t = Math.min(runTime(a), dur);
    showAt(a, t);
    if (t >= dur) {
      endRun(a);
      return;
    }
    a.raf = requestAnimationFrame(tick);
  }

  function showAt(a, t) {
    drawFrame(a, t);
    logEvents(a, t);
    setClock(a, t);
  }

  function setClock(a, t) {
    const dur = fmt(a.run.duration_s);
    const stopped = a.frozenAt !== null && a.frozenAt < a.run.duration_s;
    $("run-clock").textContent =
      (stopped ? "Stopped at " : "Run time ") + fmt(t) + " s of " + dur + " s";
  }

  /** Stops the robot (button or space bar): one POST /api/stop, never an end as well. */
  async function interrupt() {
    const a = anim;
    if (!a || a.startMs === null || a.closing || !state || state.phase !== "watch") return;
    const t = clamp(runTime(a), 0, a.run.duration_s);
    a.closing = true;
    a.frozenAt = t;
    if (a.raf) cancelAnimationFrame(a.raf);
    interruptBtn.disabled = true;
    showAt(a, t);
    // Rounded to the millisecond, never past the run's end (the server refuses a moment
    // outside the run).
    const atS = Math.min(a.run.duration_s, Math.round(t * 1000) / 1000);
    const reply = await api("POST", "/api/stop", { command: a.index, at_s: atS });
    if (anim === a) render(reply);
  }

  /** The run played to its end without a stop. */
  async function endRun(a) {
    if (a.closing) return;
    a.closing = true;
    a.frozenAt = a.run.duration_s;
    interruptBtn.disabled = true;
    const reply = await api("POST", "/api/end", { command: a.index });
    if (anim === a) render(reply);
  }

  interruptBtn.addEventListener("click", interrupt);

  const TEXT_TYPES = /^(text|search|email|url|tel|password|number|date|datetime-local|month|week|time)$/;

  function isTextField(t) {
    if (!t || !t.tagName) return false;
    if (t.isContentEditable) return true;
    const tag = t.tagName.toLowerCase();
    if (tag === "textarea" || tag === "select") return true;
    return tag === "input" && TEXT_TYPES.test((t.type || "text").toLowerCase());
  }

  // The space bar stops the robot while it runs (not from a text field, and not from another
  // button or link, which keep their own activation).
  document.addEventListener("keydown", (e) => {
    if (e.key !== " " && e.code !== "Space") return;
    if (!state || state.phase !== "watch") return;
    const t = e.target;
    if (isTextField(t)) return;
    if (t !== interruptBtn && t.closest && t.closest("button, a[href], summary")) return;
    e.preventDefault(); // no page scroll, and no second activation of a focused Interrupt
    if (!e.repeat) interrupt();
  });

  function eventText(ev) {
    const at = " at " + fmt(ev.t) + " s";
    const obj = typeof ev.object === "number" ? "object " + (ev.object + 1) : "an object";
    switch (ev.kind) {
      case "collision": return "collision" + at;
      case "stuck": return "stuck" + at;
      case "arrived": return "arrived" + at;
      case "scanned": return "scanned " + obj + at;
      case "labelled":
        return "labelled " + obj + (ev.explosive_label ? " as explosive" : " as harmless") + at;
      case "detonation": return "detonation of " + obj + at;
      default: return String(ev.kind) + at;
    }
  }

  /** Appends to the log every event the animation has reached. */
  function logEvents(a, t) {
    const log = $("event-log");
    while (a.logged < a.events.length && a.events[a.logged].t <= t) {
      const ev = a.events[a.logged++];
      const li = el("li", { "data-kind": String(ev.kind), "data-t": String(ev.t) }, eventText(ev));
      log.appendChild(li);
    }
  }

  // ---------------------------------------------------------------- state-cause

  async function enterCause(s) {
    const cmd = s.command;
    const at = typeof cmd.stopped_at === "number" ? cmd.stopped_at : 0;
    interruptBtn.hidden = true;
    $("interrupt-hint").hidden = true;
    let a = anim;
    if (!a || a.index !== cmd.index) {
      // Reloaded after the stop: show the run frozen where it was stopped.
      dropAnim();
      a = anim = newAnim(cmd);
      a.closing = true;
      a.frozenAt = at;
      showRunHeader(cmd);
    }
    $("cause-form").hidden = false;
    buildCauseForm(s.causes || []);
    setClock(a, a.frozenAt);
    logEvents(a, a.frozenAt);
    await ensureScene();
    if (anim !== a) return;
    layoutCanvas();
    showAt(a, a.frozenAt);
  }

  function buildCauseForm(causes) {
    const box = $("cause-options");
    box.textContent = "";
    const options = causes.map((c) => ({ value: c.name, text: c.text }));
    options.push({ value: "", text: "No particular reason / rather not say" });
    options.forEach((o, i) => {
      const id = "cause-" + i;
      const row = el("div", { class: "option" });
      const input = el("input", { type: "radio", name: "cause", id, value: o.value });
      row.appendChild(input);
      row.appendChild(el("label", { for: id }, o.text));
      box.appendChild(row);
    });
    const btn = $("cause-continue");
    btn.disabled = true;
    busy = false;
    const first = box.querySelector("input");
    if (first) first.focus();
  }

  $("cause-options").addEventListener("change", () => {
    $("cause-continue").disabled = false;
  });

  $("cause-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    const picked = $("cause-form").querySelector("input[name=cause]:checked");
    if (!picked || busy || !state || state.phase !== "state-cause") return;
    busy = true;
    $("cause-continue").disabled = true;
    const reply = await api("POST", "/api/statement", {
      command: state.command.index,
      cause: picked.value === "" ? null : picked.value,
    });
    busy = false;
    render(reply);
  });

  // ---------------------------------------------------------------- rate

  function enterRate(s) {
    const r = s.rating;
    if (!r || shownRating === r.number) return;
    shownRating = r.number;
    busy = false;
    const form = $("rate-form");
    form.textContent = "";
    const sc = r.scale || {};
    let focusEl;
    let readValue;
    const cont = el("button", { type: "submit", id: "rate-continue", class: "primary" }, "Continue");

    if (sc.kind === "slider") {
      const min = Number(sc.min);
      const max = Number(sc.max);
      const mid = Math.round((min + max) / 2);
      const wrap = el("div", { class: "slider-field" });
      wrap.appendChild(el("label", { for: "rating-slider", class: "question" }, r.question));
      const row = el("div", { class: "slider-row" });
      const input = el("input", {
        type: "range", id: "rating-slider", min: String(min), max: String(max), step: "1",
        value: String(mid), "aria-describedby": "rating-ends",
      });
      const out = el("output", { for: "rating-slider", id: "rating-value" }, String(mid));
      input.addEventListener("input", () => { out.textContent = input.value; });
      row.appendChild(input);
      row.appendChild(out);
      wrap.appendChild(row);
      const ends = el("p", { id: "rating-ends", class: "ends" });
      ends.appendChild(el("span", {}, min + ": " + (sc.low || "")));
      ends.appendChild(el("span", {}, max + ": " + (sc.high || "")));
      wrap.appendChild(ends);
      form.appendChild(wrap);
      focusEl = input;
      readValue = () => Number(input.value);
    } else {
      // Likert (also the fallback for an unknown kind).
      const points = Math.max(2, Number(sc.points) || 7);
      const fs = el("fieldset", { "aria-describedby": "rating-ends" });
      fs.appendChild(el("legend", { class: "question" }, r.question));
      const row = el("div", { class: "likert" });
      for (let i = 1; i <= points; i++) {
        const id = "rating-" + i;
        const cell = el("div", { class: "point" });
        cell.appendChild(el("input", { type: "radio", name: "rating", id, value: String(i) }));
        cell.appendChild(el("label", { for: id }, String(i)));
        row.appendChild(cell);
      }
      fs.appendChild(row);
      const ends = el("p", { id: "rating-ends", class: "ends" });
      ends.appendChild(el("span", {}, "1: " + (sc.low || "")));
      ends.appendChild(el("span", {}, points + ": " + (sc.high || "")));
      fs.appendChild(ends);
      form.appendChild(fs);
      cont.disabled = true;
      fs.addEventListener("change", () => { cont.disabled = false; });
      focusEl = row.querySelector("input");
      readValue = () => {
        const c = form.querySelector("input[name=rating]:checked");
        return c ? Number(c.value) : null;
      };
    }

    const actions = el("p", { class: "actions" });
    actions.appendChild(cont);
    form.appendChild(actions);
    form.onsubmit = async (e) => {
      e.preventDefault();
      const v = readValue();
      if (v === null || busy || !state || state.phase !== "rate") return;
      busy = true;
      cont.disabled = true;
      const reply = await api("POST", "/api/rating", { rating: r.number, value: v });
      busy = false;
      shownRating = null;
      render(reply);
    };
    focusEl.focus();
  }

  // ---------------------------------------------------------------- drawing

  const COLORS = {
    ground: "#f3f6ee",
    road: "#d4d4d4",
    house: "#d2b48c",
    vehicle: "#3b6fd8",
    barrier: "#c62828",
    cone: "#f28c00",
    other: "#888888",
    spot: "rgba(123, 31, 162, 0.45)",
    person: "#7b1fa2",
    route: "rgba(60, 60, 60, 0.35)",
    start: "#2e7d32",
    goal: "#111111",
    trail: "rgba(20, 20, 20, 0.6)",
    robot: "#111111",
    collision: "#d50000",
    object: "#6d4c41",
  };

  let view = null;        // {scale, cssW, cssH, dpr}
  let staticLayer = null; // the scene without the run, redrawn on resize

  async function ensureScene() {
    if (!scene) scene = await api("GET", "/api/scene");
    return scene;
  }

  /** Fits the canvas to the available width (and 70 % of the viewport height). */
  function layoutCanvas() {
    if (!scene) return;
    const [W, H] = scene.size;
    const availW = Math.max(100, $("map-wrap").clientWidth);
    const availH = Math.max(200, window.innerHeight * 0.7);
    const scale = Math.min(availW / W, availH / H);
    const cssW = Math.floor(W * scale);
    const cssH = Math.floor(H * scale);
    const dpr = window.devicePixelRatio || 1;
    if (view && view.cssW === cssW && view.cssH === cssH && view.dpr === dpr) return;
    view = { scale, cssW, cssH, dpr };
    canvas.style.width = cssW + "px";
    canvas.style.height = cssH + "px";
    canvas.width = Math.round(cssW * dpr);
    canvas.height = Math.round(cssH * dpr);
    staticLayer = document.createElement("canvas");
    staticLayer.width = canvas.width;
    staticLayer.height = canvas.height;
    drawStatic(staticLayer.getContext("2d"));
  }

  window.addEventListener("resize", () => {
    if (!anim || !scene) return;
    layoutCanvas();
    const t = anim.frozenAt !== null ? anim.frozenAt
      : anim.startMs !== null ? Math.min(runTime(anim), anim.run.duration_s) : 0;
    drawFrame(anim, t);
  });

  // Metres (y up) to CSS pixels (y down).
  const px = (x, y) => [x * view.scale, (scene.size[1] - y) * view.scale];
  const len = (m, minPx) => Math.max(m * view.scale, minPx);

  function polyPath(ctx, pts) {
    ctx.beginPath();
    pts.forEach((p, i) => {
      const [x, y] = px(p[0], p[1]);
      if (i === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
    });
    ctx.closePath();
  }

  function disc(ctx, x, y, r) {
    ctx.beginPath();
    ctx.arc(x, y, r, 0, Math.PI * 2);
  }

  function centre(shape) {
    if (shape.circle) return [shape.circle[0], shape.circle[1]];
    const pts = shape.polygon || [];
    const n = pts.length || 1;
    return [pts.reduce((s, p) => s + p[0], 0) / n, pts.reduce((s, p) => s + p[1], 0) / n];
  }

  function square(ctx, p, size, fill) {
    const [x, y] = px(p[0], p[1]);
    ctx.fillStyle = fill;
    ctx.fillRect(x - size / 2, y - size / 2, size, size);
    ctx.strokeStyle = "#ffffff";
    ctx.lineWidth = 1.5;
    ctx.strokeRect(x - size / 2, y - size / 2, size, size);
  }

  function drawStatic(ctx) {
    ctx.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    ctx.fillStyle = COLORS.ground;
    ctx.fillRect(0, 0, view.cssW, view.cssH);
    // Roads.
    ctx.fillStyle = COLORS.road;
    for (const r of scene.roads || []) {
      const [x0, y0] = px(r.min[0], r.max[1]);
      const [x1, y1] = px(r.max[0], r.min[1]);
      ctx.fillRect(x0, y0, x1 - x0, y1 - y0);
    }
    // Obstacles.
    for (const o of scene.obstacles || []) {
      ctx.fillStyle = COLORS[o.kind] || COLORS.other;
      ctx.strokeStyle = "rgba(0, 0, 0, 0.35)";
      ctx.lineWidth = 1;
      if (o.circle) {
        const [x, y] = px(o.circle[0], o.circle[1]);
        disc(ctx, x, y, len(o.circle[2], 2.5));
      } else if (o.polygon) {
        polyPath(ctx, o.polygon);
      } else continue;
      ctx.fill();
      ctx.stroke();
    }
    // Spots where people may stand: faint rings (or outlines).
    ctx.strokeStyle = COLORS.spot;
    ctx.lineWidth = 1.5;
    for (const p of scene.people || []) {
      if (p.circle) {
        const [x, y] = px(p.circle[0], p.circle[1]);
        disc(ctx, x, y, len(p.circle[2], 5));
      } else if (p.polygon) {
        polyPath(ctx, p.polygon);
      } else continue;
      ctx.stroke();
    }
    // The route: a faint dashed line, start and goal as squares.
    const route = scene.route || [];
    if (route.length) {
      ctx.strokeStyle = COLORS.route;
      ctx.lineWidth = 1.5;
      ctx.setLineDash([6, 5]);
      ctx.beginPath();
      route.forEach((p, i) => {
        const [x, y] = px(p[0], p[1]);
        if (i === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
      });
      ctx.stroke();
      ctx.setLineDash([]);
      const size = len(1.6, 10);
      square(ctx, route[0], size, COLORS.start);
      square(ctx, route[route.length - 1], size, COLORS.goal);
    }
  }

  /** The robot's centre at run time t, interpolated linearly along run.path. */
  function positionAt(path, t) {
    if (!path.length) {
      const r0 = (scene.route || [[0, 0]])[0];
      return [r0[0], r0[1]];
    }
    if (t <= path[0][0]) return [path[0][1], path[0][2]];
    let lo = 0;
    let hi = path.length - 1;
    if (t >= path[hi][0]) return [path[hi][1], path[hi][2]];
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (path[mid][0] <= t) lo = mid; else hi = mid;
    }
    const a = path[lo];
    const b = path[hi];
    const f = b[0] > a[0] ? (t - a[0]) / (b[0] - a[0]) : 0;
    return [a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f];
  }

  function cross(ctx, p, size) {
    const [x, y] = px(p[0], p[1]);
    ctx.strokeStyle = "#ffffff";
    ctx.lineWidth = 5;
    for (const pass of [0, 1]) {
      if (pass) { ctx.strokeStyle = COLORS.collision; ctx.lineWidth = 3; }
      ctx.beginPath();
      ctx.moveTo(x - size, y - size); ctx.lineTo(x + size, y + size);
      ctx.moveTo(x + size, y - size); ctx.lineTo(x - size, y + size);
      ctx.stroke();
    }
  }

  function ring(ctx, p, r, color, dashed) {
    const [x, y] = px(p[0], p[1]);
    ctx.strokeStyle = color;
    ctx.lineWidth = 2.5;
    if (dashed) ctx.setLineDash([4, 3]);
    disc(ctx, x, y, r);
    ctx.stroke();
    ctx.setLineDash([]);
  }

  /** One frame: the scene, who is present, the objects, the trail, the events so far, the robot. */
  function drawFrame(a, t) {
    if (!scene || !view || !staticLayer) return;
    const ctx = canvas.getContext("2d");
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(staticLayer, 0, 0);
    ctx.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    const run = a.run;
    // People present in this run.
    ctx.fillStyle = COLORS.person;
    for (const i of run.present || []) {
      const p = (scene.people || [])[i];
      if (!p) continue;
      if (p.polygon) {
        ctx.globalAlpha = 0.25;
        polyPath(ctx, p.polygon);
        ctx.fill();
        ctx.globalAlpha = 1;
      }
      const c = centre(p);
      const [x, y] = px(c[0], c[1]);
      disc(ctx, x, y, len(p.circle ? p.circle[2] : 0.5, 5));
      ctx.fill();
    }
    // Events reached so far, and what they say about the objects.
    const reached = a.events.filter((ev) => ev.t <= t);
    const labels = {};
    for (const ev of reached) {
      if (ev.kind === "labelled") labels[ev.object] = ev.explosive_label ? "#d50000" : "#2e7d32";
    }
    // Patrol objects: small diamonds.
    (run.objects || []).forEach((o, i) => {
      const [x, y] = px(o.at[0], o.at[1]);
      const s = 5;
      ctx.fillStyle = labels[i] || COLORS.object;
      ctx.beginPath();
      ctx.moveTo(x, y - s); ctx.lineTo(x + s, y); ctx.lineTo(x, y + s); ctx.lineTo(x - s, y);
      ctx.closePath();
      ctx.fill();
    });
    // The driven trail.
    const path = run.path || [];
    if (path.length) {
      ctx.strokeStyle = COLORS.trail;
      ctx.lineWidth = 2.5;
      ctx.lineJoin = "round";
      ctx.lineCap = "round";
      ctx.beginPath();
      let [x, y] = px(path[0][1], path[0][2]);
      ctx.moveTo(x, y);
      for (let i = 1; i < path.length && path[i][0] <= t; i++) {
        [x, y] = px(path[i][1], path[i][2]);
        ctx.lineTo(x, y);
      }
      const now = positionAt(path, t);
      [x, y] = px(now[0], now[1]);
      ctx.lineTo(x, y);
      ctx.stroke();
    }
    for (const ev of reached) {
      const obj = (run.objects || [])[ev.object];
      if (ev.kind === "collision" && ev.at) cross(ctx, ev.at, len(0.9, 6));
      else if (ev.kind === "stuck") ring(ctx, positionAt(path, ev.t), len(1.5, 10), COLORS.collision, true);
      else if (ev.kind === "arrived") ring(ctx, positionAt(path, ev.t), len(1.5, 10), COLORS.start, false);
      else if (ev.kind === "scanned" && obj) ring(ctx, obj.at, 9, COLORS.object, true);
      else if (ev.kind === "detonation" && obj) burst(ctx, obj.at);
    }
    // The robot.
    const r = positionAt(path, t);
    const [rx, ry] = px(r[0], r[1]);
    disc(ctx, rx, ry, len(scene.robot_radius || 0.5, 5));
    ctx.fillStyle = COLORS.robot;
    ctx.fill();
    ctx.strokeStyle = "#ffffff";
    ctx.lineWidth = 2;
    ctx.stroke();
  }

  function burst(ctx, p) {
    const [x, y] = px(p[0], p[1]);
    ctx.fillStyle = "#ff6d00";
    ctx.beginPath();
    for (let i = 0; i < 16; i++) {
      const r = i % 2 ? 6 : 14;
      const a = (i * Math.PI) / 8;
      ctx.lineTo(x + r * Math.cos(a), y + r * Math.sin(a));
    }
    ctx.closePath();
    ctx.fill();
  }

  // ---------------------------------------------------------------- boot

  window.addEventListener("pagehide", () => {
    if (token && navigator.sendBeacon) {
      navigator.sendBeacon("/api/leave", JSON.stringify({ token }));
    }
  });

  // Back from the back/forward cache (after a pagehide, so a `left` event): ask the server again.
  window.addEventListener("pageshow", (e) => {
    if (e.persisted && token) location.reload();
  });

  const m = location.pathname.match(/^\/p\/([^/]+)\/?$/);
  if (m) {
    token = decodeURIComponent(m[1]);
    storeSet(token);
    startSession();
  } else {
    showConsent();
  }
})();
