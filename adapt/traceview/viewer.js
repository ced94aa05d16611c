// adapt trace viewer: everything runs locally on the data embedded in the page.
"use strict";
(function () {
  const DATA = JSON.parse(document.getElementById("trace-data").textContent);
  const cycles = DATA.cycles;
  const K = DATA.K;
  const ROW = 22;
  const byCycle = new Map();
  cycles.forEach((c, i) => byCycle.set(c.c, i));

  function el(tag, cls, text) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined && text !== null) e.textContent = text;
    return e;
  }

  // ---------- header ----------
  document.getElementById("trace-title").textContent = DATA.title;
  const summary = document.getElementById("run-summary");
  const h = DATA.header || {}, f = DATA.footer;
  const nDecisions = cycles.filter((c) => c.op || c.imp).length;
  const bits = [["decisions", String(f ? f.decisions : nDecisions)], ["level", String(DATA.level)]];
  if (h.seed !== undefined && h.seed !== null) bits.push(["seed", String(h.seed)]);
  if (f) bits.push(["stopped", (f.stop_reason || "?") + (f.error ? ": " + f.error : "")]);
  else bits.push(["stopped", "no footer (interrupted run?)"]);
  if (h.engine) bits.push(["engine", h.engine + (h.kernel ? " (" + h.kernel + ")" : "")]);
  if (h.files && h.files.length) bits.push(["rules", h.files.join(", ")]);
  bits.forEach(([k, v], i) => {
    if (i) summary.appendChild(document.createTextNode("  ·  "));
    summary.appendChild(document.createTextNode(k + " "));
    summary.appendChild(el("b", null, v));
  });
  const notices = (DATA.notices || []).slice();
  if (Array.isArray(h.absent) && h.absent.length)  // a trace of the Soar engine
    notices.push("Not in this trace (the engine does not report them): " + h.absent.join(", ") + ".");
  if (notices.length) {
    const n = document.getElementById("notices");
    n.hidden = false;
    n.textContent = notices.join(" ");
  }

  // ---------- working memory at a cycle (keyframes + deltas) ----------
  let cacheIndex = -1;
  let cacheWM = new Map();
  function applyDelta(wm, entry) {
    if (entry.x) for (const t of entry.x) wm.delete(t);
    if (entry.a) for (const w of entry.a) wm.set(w[0], w);
  }
  function wmAt(index) {
    if (index === cacheIndex) return cacheWM;
    let start, wm;
    if (cacheIndex >= 0 && index > cacheIndex && (K === 0 || index - cacheIndex <= K)) {
      wm = cacheWM; start = cacheIndex + 1;
    } else {
      const k = K ? Math.floor((index + 1) / K) * K - 1 : -1;
      wm = new Map();
      if (k >= 0 && DATA.keyframes[String(k)]) {
        for (const w of DATA.keyframes[String(k)]) wm.set(w[0], w);
        start = k + 1;
      } else start = 0;
    }
    for (let i = start; i <= index; i++) applyDelta(wm, cycles[i]);
    cacheIndex = index; cacheWM = wm;
    return wm;
  }

  // ---------- timeline (virtualised) ----------
  const timeline = document.getElementById("timeline");
  const spacer = document.getElementById("timeline-spacer");
  const onlyImp = document.getElementById("only-impasses");
  let rows = cycles.map((_, i) => i);
  let selected = -1;
  const rendered = new Map();

  function decisionText(c) {
    const pad = "   ".repeat(c.lv || 0);
    if (c.imp) return pad + "==>S: " + c.imp[1] + " (" + c.imp[0] + ")";
    if (c.op) return pad + "O: " + c.op[0] + " (" + c.op[1] + ")";
    return pad + "—";
  }
  function makeRow(pos) {
    const i = rows[pos], c = cycles[i];
    const r = el("div", "row" + (c.imp ? " impasse" : "") + (i === selected ? " selected" : ""));
    r.style.top = pos * ROW + "px";
    r.dataset.d = String(c.c);
    r.dataset.index = String(i);
    r.setAttribute("role", "option");
    r.appendChild(el("span", "d", String(c.c)));
    r.appendChild(el("span", "what", decisionText(c)));
    if (c.f) r.appendChild(el("span", "nf", c.f.length + "⚡"));
    return r;
  }
  function renderRows() {
    const top = timeline.scrollTop, height = timeline.clientHeight || 600;
    const first = Math.max(0, Math.floor(top / ROW) - 10);
    const last = Math.min(rows.length - 1, Math.ceil((top + height) / ROW) + 10);
    for (const [pos, node] of rendered) {
      if (pos < first || pos > last) { node.remove(); rendered.delete(pos); }
    }
    for (let pos = first; pos <= last; pos++) {
      if (!rendered.has(pos)) {
        const node = makeRow(pos);
        rendered.set(pos, node);
        timeline.appendChild(node);
      }
    }
  }
  function resetRows() {
    rows = onlyImp.checked ? cycles.map((_, i) => i).filter((i) => cycles[i].imp) : cycles.map((_, i) => i);
    spacer.style.height = rows.length * ROW + "px";
    for (const node of rendered.values()) node.remove();
    rendered.clear();
    renderRows();
    document.getElementById("timeline-count").textContent =
      rows.length + (onlyImp.checked ? " impasses" : " decision cycles");
  }
  timeline.addEventListener("scroll", renderRows, { passive: true });
  onlyImp.addEventListener("change", () => { resetRows(); scrollToIndex(selected); });
  timeline.addEventListener("click", (ev) => {
    const r = ev.target.closest(".row");
    if (r) select(Number(r.dataset.index));
  });
  function scrollToIndex(i) {
    const pos = rows.indexOf(i);
    if (pos < 0) return;
    const top = pos * ROW;
    if (top < timeline.scrollTop || top > timeline.scrollTop + timeline.clientHeight - ROW) {
      timeline.scrollTop = Math.max(0, top - timeline.clientHeight / 2);
    }
    renderRows();
  }
  timeline.addEventListener("keydown", (ev) => {
    const pos = rows.indexOf(selected);
    const page = Math.max(1, Math.floor(timeline.clientHeight / ROW) - 1);
    const moves = { ArrowDown: 1, ArrowUp: -1, PageDown: page, PageUp: -page };
    let next = null;
    if (ev.key in moves) next = Math.min(rows.length - 1, Math.max(0, pos + moves[ev.key]));
    else if (ev.key === "Home") next = 0;
    else if (ev.key === "End") next = rows.length - 1;
    if (next !== null && rows.length) { ev.preventDefault(); select(rows[next]); }
  });
  document.getElementById("goto").addEventListener("change", (ev) => {
    const d = Number(ev.target.value);
    let i = byCycle.get(d);
    if (i === undefined) {  // nearest cycle at or after d
      i = cycles.findIndex((c) => c.c >= d);
      if (i < 0) i = cycles.length - 1;
    }
    if (onlyImp.checked && !cycles[i].imp) { onlyImp.checked = false; resetRows(); }
    select(i);
  });

  // ---------- detail panels ----------
  function wmeNode(w, showTT) {
    const s = el("span", "wme" + (w[4] & 1 ? " acc" : ""));
    if (showTT) s.appendChild(el("span", "tt", w[0] + ": "));
    s.appendChild(el("span", "attr", "^" + w[2]));
    s.appendChild(document.createTextNode(" "));
    s.appendChild(el("span", "val", w[3]));
    return s;
  }
  function wmeText(w) {
    return "(" + w[0] + ": " + w[1] + " ^" + w[2] + " " + w[3] + (w[4] & 1 ? " +" : "") + ")";
  }
  function groupById(wm) {
    const g = new Map();
    for (const w of wm.values()) {
      if (!g.has(w[1])) g.set(w[1], []);
      g.get(w[1]).push(w);
    }
    for (const list of g.values()) list.sort((a, b) => (a[2] < b[2] ? -1 : a[2] > b[2] ? 1 : a[0] - b[0]));
    return g;
  }
  const openIds = new Set(["S1"]);
  function renderWM(index) {
    const tree = document.getElementById("wm-tree");
    tree.textContent = "";
    if (DATA.level < 4) {
      tree.appendChild(el("div", "empty", "working memory needs a trace written at level 4 or more"));
      return;
    }
    const wm = wmAt(index);
    const groups = groupById(wm);
    const root = document.getElementById("wm-root").value.trim() || "S1";
    const showTT = document.getElementById("wm-tt").checked;
    document.getElementById("wm-size").textContent = "(" + wm.size + " WMEs at decision " + cycles[index].c + ")";
    if (!groups.has(root)) {
      tree.appendChild(el("div", "empty", root + " has no WMEs at this decision"));
      return;
    }
    const ul = el("ul");
    ul.appendChild(idNode(root, groups, showTT, new Set([root]), root));
    tree.appendChild(ul);
  }
  function idNode(id, groups, showTT, path, key) {
    const li = el("li", "wm-node");
    li.dataset.id = id;
    li.dataset.key = key;
    const head = el("span", "wm-head");
    head.appendChild(el("span", "wm-id", id));
    const kids = groups.get(id) || [];
    head.appendChild(el("span", "muted", "  " + kids.length + (kids.length === 1 ? " WME" : " WMEs")));
    li.appendChild(head);
    const build = () => {
      const ul = el("ul");
      for (const w of kids) {
        const isId = (w[4] & 2) && groups.has(w[3]);
        if (isId && !path.has(w[3])) {
          const child = idNode(w[3], groups, showTT, new Set([...path, w[3]]), key + "/" + w[2] + "/" + w[3]);
          child.querySelector(".wm-head").prepend(wmeNode(w, showTT), document.createTextNode(" "));
          child.querySelector(".wm-head .wm-id").remove();
          ul.appendChild(child);
        } else {
          const leaf = el("li", "wm-leaf");
          leaf.appendChild(wmeNode(w, showTT));
          if (isId) leaf.appendChild(el("span", "seen", "  (above)"));
          ul.appendChild(leaf);
        }
      }
      li.appendChild(ul);
    };
    if (openIds.has(key)) { li.classList.add("open"); build(); }
    head.addEventListener("click", () => {
      if (li.classList.toggle("open")) { openIds.add(key); if (!li.querySelector("ul")) build(); }
      else openIds.delete(key);
    });
    return li;
  }
  document.getElementById("wm-root").addEventListener("change", () => { openIds.add(document.getElementById("wm-root").value.trim()); renderWM(selected); });
  document.getElementById("wm-tt").addEventListener("change", () => renderWM(selected));
  document.getElementById("wm-expand").addEventListener("click", () => {
    // open three levels below the root
    for (let n = 0; n < 3; n++) {
      document.querySelectorAll("#wm-tree .wm-node:not(.open) > .wm-head").forEach((hd) => hd.click());
    }
  });
  document.getElementById("wm-collapse").addEventListener("click", () => {
    openIds.clear(); openIds.add(document.getElementById("wm-root").value.trim()); renderWM(selected);
  });

  function renderSummary(c) {
    const box = document.getElementById("decision-summary");
    box.textContent = "";
    const left = el("div");
    left.appendChild(el("div", "muted", "decision " + c.c + (c.lv ? " · goal level " + c.lv : "")));
    left.appendChild(el("div", "big" + (c.imp ? " impasse" : ""), decisionText(c).trim()));
    box.appendChild(left);
    if (c.cand) {
      const cands = el("div", "cands");
      cands.appendChild(el("div", "muted", "candidates and preferences"));
      for (const [id, name, prefs] of c.cand) {
        const line = el("div", null, id + " (" + name + ")");
        for (const [k, r] of prefs) line.appendChild(el("span", "pref", r === null ? k : k + " " + r));
        cands.appendChild(line);
      }
      box.appendChild(cands);
    }
    if (c.p) box.appendChild(el("div", "muted", "phases: " + c.p.join(" → ")));
  }
  function renderFirings(c) {
    const box = document.getElementById("firings");
    box.textContent = "";
    if (DATA.level < 3) { box.appendChild(el("div", "empty", "firings need a trace of level 3 or more")); return; }
    if (!c.f && !c.r) { box.appendChild(el("div", "empty", "no firings in this cycle")); return; }
    for (const [phase, rule, level, support, bindings, wmes] of c.f || []) {
      const d = el("div", "firing");
      d.dataset.rule = rule;
      d.appendChild(el("span", "rule", rule));
      d.appendChild(el("span", "meta", phase + " · " + (support ? support + "-support · " : "") + "level " + level));
      const b = el("div", "bindings");
      for (const [v, val] of bindings) {
        const s = el("span", "binding");
        s.appendChild(el("span", "var", v));
        s.appendChild(document.createTextNode(" = " + val));
        b.appendChild(s);
      }
      d.appendChild(b);
      if (wmes.length) d.appendChild(el("div", "matched", "matched " + wmes.join(", ")));
      box.appendChild(d);
    }
    for (const [phase, rule, level] of c.r || []) {
      const d = el("div", "firing retraction");
      d.appendChild(el("span", "rule", "retract " + rule));
      d.appendChild(el("span", "meta", phase + " · level " + level));
      box.appendChild(d);
    }
  }
  function renderGoals(c, index) {
    const box = document.getElementById("goals");
    box.textContent = "";
    if (c.imp) {
      const d = el("div", "goal impasse-line");
      d.appendChild(el("span", "imp", "impasse: " + c.imp[0]));
      d.appendChild(document.createTextNode(" → substate " + c.imp[1] + (c.imp[2].length ? ", items " + c.imp[2].join(" ") : "")));
      box.appendChild(d);
    }
    if (c.rg) box.appendChild(el("div", "goal", "removed substates: " + c.rg.join(", ")));
    if (DATA.level >= 4) {
      const wm = wmAt(index);
      const sup = new Map(), imp = new Map(), states = new Set();
      for (const w of wm.values()) {
        if (w[2] === "superstate" && (w[4] & 2)) sup.set(w[1], w[3]);
        if (w[2] === "type" && w[3] === "state") states.add(w[1]);
        if (w[2] === "impasse") imp.set(w[1], w[3]);
        if (w[2] === "attribute") imp.set(w[1], (imp.get(w[1]) || "") + "/" + w[3]);
      }
      const depth = (s) => { let n = 0; while (sup.has(s) && n < 100) { s = sup.get(s); n++; } return n; };
      const order = [...states].sort((a, b) => depth(a) - depth(b));
      box.appendChild(el("div", "muted", "goal stack"));
      for (const s of order) {
        const g = el("div", "goal", "   ".repeat(depth(s)) + s);
        if (imp.has(s)) g.appendChild(el("span", "imp", "  (" + imp.get(s) + ")"));
        box.appendChild(g);
      }
    }
    if (!box.childNodes.length) box.appendChild(el("div", "empty", "top state only"));
    // selected operators of the same cycle, one per goal level, from the decision record
  }
  function renderSide(c) {
    const framePanel = document.getElementById("frame-panel");
    const frame = document.getElementById("mmd-frame");
    frame.textContent = "";
    let src = c.frame, from = c.c;
    if (!src) {  // the latest frame at or before this decision
      for (let i = byCycle.get(c.c); i >= 0; i--) if (cycles[i].frame) { src = cycles[i].frame; from = cycles[i].c; break; }
    }
    framePanel.hidden = !src;
    if (src) {
      const img = el("img");
      img.src = src; img.alt = "MMD frame of decision " + from;
      frame.appendChild(img);
      if (from !== c.c) frame.appendChild(el("div", "muted", "frame of decision " + from));
    }
    const sch = document.getElementById("schema-events");
    sch.textContent = "";
    if (c.schema) for (const [ev, name, data] of c.schema) {
      const d = el("div", "schema-event");
      d.appendChild(el("b", null, name));
      d.appendChild(document.createTextNode(" " + ev + (data ? " " + data : "")));
      sch.appendChild(d);
    } else sch.appendChild(el("div", "empty", "none in this cycle"));
    const ch = document.getElementById("wm-changes");
    ch.textContent = "";
    if (DATA.level >= 4) {
      const before = selected > 0 ? new Map(wmAt(selected - 1)) : new Map();
      wmAt(selected);
      for (const t of c.x || []) if (before.has(t)) ch.appendChild(el("div", "change rem", wmeText(before.get(t))));
      for (const w of c.a || []) ch.appendChild(el("div", "change add", wmeText(w)));
      if (!ch.childNodes.length) ch.appendChild(el("div", "empty", "no changes"));
    } else ch.appendChild(el("div", "empty", "needs a level-4 trace"));
    const out = document.getElementById("output");
    out.textContent = (c.w || "") + (c.m ? c.m.join("\n") : "");
    if (!out.textContent) out.appendChild(el("span", "empty", "no output"));
  }

  // ---------- run panels: schema network, MMD per frame, learned look ----------
  const netAt = [], frAt = [], lookAt = [], statusAt = [];  // statusAt: [index, schema, status]
  cycles.forEach((c, i) => {
    if (c.net) netAt.push(i);
    if (c.fr) frAt.push(i);
    if (c.look) lookAt.push(i);
    for (const [ev, name, data] of c.schema || []) {
      if (ev !== "status" || !data) continue;
      try { const d = JSON.parse(data); if (d && d.status) statusAt.push([i, name, d.status]); } catch (e) { /* not JSON */ }
    }
  });
  function statusesBetween(from, to) {
    // the last status of each schema in [from, to]: the runner writes a status event
    // after the network record of the same cycle, so that cycle's events count too
    const out = new Map();
    for (const [i, name, status] of statusAt) if (i >= from && i <= to) out.set(name, status);
    return out;
  }
  function latest(list, index) {  // the last entry of list <= index, or -1
    let lo = 0, hi = list.length - 1, best = -1;
    while (lo <= hi) {
      const mid = (lo + hi) >> 1;
      if (list[mid] <= index) { best = list[mid]; lo = mid + 1; } else hi = mid - 1;
    }
    return best;
  }
  function esc(t) {
    return String(t).replace(/&/g, "&amp;").replace(/[<]/g, "&lt;").replace(/>/g, "&gt;").replace(/"/g, "&quot;");
  }
  function fmt(v, digits) {
    if (v === null || v === undefined) return "—";
    if (typeof v === "number") return Number.isInteger(v) ? String(v) : v.toFixed(digits === undefined ? 2 : digits);
    if (typeof v === "boolean") return v ? "yes" : "no";
    return String(v);
  }
  const STATUS = { running: "#1a7f37", complete: "#1a7f37", waiting: "#b45309", executing: "#2f6fab",
                   idle: "#8a949e", lost: "#cf222e", failed: "#cf222e" };
  const FILL = { perceptual: "#e5effa", motor: "#fdebd3" };
  function layers(nodes, edges) {
    // longest path from a node without providers: providers left, consumers right
    const names = nodes.map((n) => n[0]), layer = new Map(names.map((n) => [n, 0]));
    for (let pass = 0; pass < names.length; pass++) {
      let moved = false;
      for (const [a, b] of edges) {
        if (layer.has(a) && layer.has(b) && layer.get(b) < layer.get(a) + 1 && layer.get(a) + 1 < names.length) {
          layer.set(b, layer.get(a) + 1); moved = true;
        }
      }
      if (!moved) break;
    }
    return layer;
  }
  function renderNetwork(index) {
    const box = document.getElementById("network-graph");
    const when = document.getElementById("network-when");
    const at = latest(netAt, index);
    box.textContent = "";
    if (at < 0) { when.textContent = ""; box.appendChild(el("div", "empty", "no schema yet")); return; }
    const net = cycles[at].net;
    const later = statusesBetween(at, index);  // statuses change without the network changing
    when.textContent = "(frame " + fmt(net.frame) + ", as changed at decision " + cycles[at].c + ")";
    box.dataset.decision = String(cycles[at].c);
    const layer = layers(net.nodes, net.edges);
    const cols = new Map();
    for (const n of net.nodes) {
      const k = layer.get(n[0]);
      if (!cols.has(k)) cols.set(k, []);
      cols.get(k).push(n);
    }
    const W = 168, H = 46, GX = 74, GY = 16, PAD = 8;
    const pos = new Map();
    let width = 0, height = 0;
    for (const [k, list] of cols) {
      list.forEach((n, j) => {
        const x = PAD + k * (W + GX), y = PAD + j * (H + GY);
        pos.set(n[0], [x, y]);
        width = Math.max(width, x + W + PAD); height = Math.max(height, y + H + PAD);
      });
    }
    let svg = '<svg viewBox="0 0 ' + width + " " + height + '" width="' + width + '" height="' + height +
      '" role="img" aria-label="schema network">' +
      '<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto">' +
      '<path d="M0,0 L10,5 L0,10 z" fill="#8a949e"/></marker></defs>';
    for (const [a, b, port] of net.edges) {
      if (!pos.has(a) || !pos.has(b)) continue;
      const [xa, ya] = pos.get(a), [xb, yb] = pos.get(b);
      const x1 = xa + W, y1 = ya + H / 2, x2 = xb, y2 = yb + H / 2, mx = (x1 + x2) / 2;
      svg += '<g class="edge" data-from="' + esc(a) + '" data-to="' + esc(b) + '" data-port="' + esc(port) + '">' +
        '<path marker-end="url(#arrow)" d="M' + x1 + "," + y1 + " C" + mx + "," + y1 + " " + mx + "," + y2 + " " + (x2 - 2) + "," + y2 + '"/>' +
        '<text x="' + mx + '" y="' + ((y1 + y2) / 2 - 4) + '" text-anchor="middle">' + esc(port) + "</text></g>";
    }
    for (const [name, type, kind, first, origin, details] of net.nodes) {
      const [x, y] = pos.get(name);
      const status = later.has(name) ? later.get(name) : first;
      const tip = name + " (" + type + ", " + kind + ", " + origin + "): " + status +
        Object.entries(details).map(([k, v]) => "\n" + k + " = " + fmt(v, 3)).join("");
      svg += '<g class="node ' + esc(origin) + '" data-name="' + esc(name) + '" data-status="' + esc(status) +
        '" data-kind="' + esc(kind) + '"><title>' + esc(tip) + "</title>" +
        '<rect x="' + x + '" y="' + y + '" width="' + W + '" height="' + H + '" rx="7" fill="' + (FILL[kind] || "#f3f3f3") +
        '" stroke="' + (STATUS[status] || "#8a949e") + '"/>' +
        '<text class="name" x="' + (x + 10) + '" y="' + (y + 18) + '">' + esc(name) + "</text>" +
        '<text class="sub" x="' + (x + 10) + '" y="' + (y + 35) + '">' + esc(type + " · " + status) + "</text></g>";
    }
    svg += "</svg>";
    box.innerHTML = svg;
    const legend = el("div", "legend");
    legend.innerHTML = 'fill: <span class="key" style="background:' + FILL.perceptual + '"></span>perceptual' +
      '<span class="key" style="background:' + FILL.motor + '"></span>motor · border: status (green running, amber waiting, red lost/failed) · dashed: spawned bottom-up · arrows: ports';
    box.appendChild(legend);
  }
  const series = frAt.map((i) => cycles[i].fr);
  function renderChart(currentFrame) {
    const box = document.getElementById("mmd-chart");
    box.textContent = "";
    if (series.length < 2) return;
    const W = 600, H = 64, n = series.length;
    const cap = 3;  // pixel error drawn up to 3 px
    const xs = (k) => (k / (n - 1)) * (W - 4) + 2;
    let pts = "", bars = "", maxU = 1;
    for (const f of series) maxU = Math.max(maxU, f[2] || 0);
    series.forEach((f, k) => {
      const e = f[3] && f[3].pixel_error !== null && f[3].pixel_error !== undefined ? Math.min(f[3].pixel_error, cap) : null;
      if (e !== null) pts += xs(k).toFixed(1) + "," + (H - 2 - (e / cap) * (H - 6)).toFixed(1) + " ";
      if (f[2]) bars += '<rect class="unexp" x="' + (xs(k) - 1).toFixed(1) + '" y="' + (H - 2 - (f[2] / maxU) * 20).toFixed(1) +
        '" width="2" height="' + ((f[2] / maxU) * 20).toFixed(1) + '"/>';
    });
    const k = series.findIndex((f) => f[0] === currentFrame);
    const now = k >= 0 ? '<line class="now" x1="' + xs(k) + '" x2="' + xs(k) + '" y1="0" y2="' + H + '"/>' : "";
    box.innerHTML = '<svg viewBox="0 0 ' + W + " " + H + '" preserveAspectRatio="none"><polyline class="err" points="' + pts +
      '"/>' + bars + now + "</svg>";
    box.firstChild.addEventListener("click", (ev) => {
      const r = box.firstChild.getBoundingClientRect();
      const j = Math.round(((ev.clientX - r.left) / r.width) * (n - 1));
      select(frAt[Math.max(0, Math.min(n - 1, j))]);
    });
    const cap2 = el("div", "legend", "frames " + fmt(series[0][0]) + "–" + fmt(series[n - 1][0]) +
      ": blue, the camera's pixel error (0–3 px); red, unexpected regions (up to " + maxU + ")");
    box.appendChild(cap2);
  }
  function renderFrame(index) {
    const sum = document.getElementById("mmd-summary"), regions = document.getElementById("mmd-regions");
    const when = document.getElementById("mmd-when");
    const at = latest(frAt, index);
    sum.textContent = ""; regions.textContent = "";
    if (at < 0) { when.textContent = ""; sum.appendChild(el("div", "empty", "no frame yet")); renderChart(null); return; }
    const [frame, t, unexpected, mmd, regs] = cycles[at].fr;
    when.textContent = "(frame " + fmt(frame) + ", t = " + fmt(t, 3) + " s)";
    sum.dataset.frame = String(frame);
    const items = [["aligned", mmd ? mmd.aligned : null], ["pixel error", mmd ? mmd.pixel_error : null],
                   ["inliers", mmd ? mmd.inliers : null], ["regions", mmd ? mmd.regions : regs.length],
                   ["unexpected", unexpected], ["ms", mmd ? mmd.ms : null]];
    for (const [k, v] of items) {
      const d = el("div", null, k + " ");
      const b = el("b", null, fmt(v));
      if ((k === "aligned" && v === false) || (k === "unexpected" && v > 0)) b.className = "bad";
      d.appendChild(b);
      d.dataset.key = k;
      sum.appendChild(d);
    }
    renderChart(frame);
    if (regs.length) {
      const table = el("table");
      const head = el("tr");
      for (const h of ["id", "box (x y w h)", "area", "age", "monitored by"]) head.appendChild(el("th", null, h));
      table.appendChild(head);
      for (const [id, x, y, w, h, area, expected, owner, age] of regs) {
        const tr = el("tr", expected ? "expected" : "unexpected");
        for (const v of [id, x + " " + y + " " + w + " " + h, area, age, expected ? owner : "unexpected"]) tr.appendChild(el("td", null, fmt(v)));
        table.appendChild(tr);
      }
      regions.appendChild(table);
    }
  }
  function renderLook(index) {
    const panel = document.getElementById("look-panel"), grid = document.getElementById("look-grid");
    const when = document.getElementById("look-when");
    grid.textContent = "";
    if (!lookAt.length) { panel.hidden = true; return; }
    panel.hidden = false;
    const at = latest(lookAt, index);
    if (at < 0) { when.textContent = ""; grid.appendChild(el("div", "empty", "nothing learned yet")); return; }
    const look = cycles[at].look;
    when.textContent = "(" + fmt(look.stage) + ", " + fmt(look.passes) + " passes, as of frame " + fmt(look.frame) + ")";
    grid.dataset.frame = String(look.frame);
    for (const [name, coverage, w, h, image] of look.surfaces) {
      const fig = el("figure");
      fig.dataset.surface = name;
      if (image) {
        const img = el("img");
        img.src = image; img.alt = name; img.title = name + ": " + w + "x" + h + " texels";
        fig.appendChild(img);
      }
      const cap = el("figcaption");
      cap.appendChild(el("span", "n", name));
      cap.appendChild(document.createTextNode(" · " + Math.round(100 * (coverage || 0)) + "% seen"));
      fig.appendChild(cap);
      grid.appendChild(fig);
    }
  }
  const hasRun = netAt.length > 0 || frAt.length > 0;
  document.getElementById("run-panels").hidden = !hasRun;

  // ---------- the run's mmd.mp4 beside the trace: shown at the selected frame ----------
  const video = document.getElementById("mmd-video");
  const VIDEO = DATA.video || null;
  const frameAt = new Map();  // frame index -> the first cycle index with that frame's record
  frAt.forEach((i) => { if (!frameAt.has(cycles[i].fr[0])) frameAt.set(cycles[i].fr[0], i); });
  if (VIDEO) {
    document.getElementById("video-panel").hidden = false;
    video.src = VIDEO.src;
    video.addEventListener("error", () => {
      document.getElementById("video-note").textContent = "this browser cannot play " + VIDEO.src +
        " (browsers play it when the run wrote it as VP9: outputs.video_codec: vp9)";
    });
    video.addEventListener("timeupdate", () => {  // playing moves the selection along
      if (video.paused || !VIDEO.fps) return;
      const i = frameAt.get(Math.floor(video.currentTime * VIDEO.fps));
      if (i !== undefined && i !== selected) select(i, true);
    });
  }
  function seekVideo(index) {
    if (!VIDEO || !VIDEO.fps || !video.paused) return;
    const at = latest(frAt, index);
    if (at < 0) return;
    const t = (cycles[at].fr[0] + 0.5) / VIDEO.fps;  // the middle of the frame's interval
    if (Math.abs(video.currentTime - t) > 0.25 / VIDEO.fps) video.currentTime = t;
  }

  function select(index, fromVideo) {
    if (index < 0 || index >= cycles.length) return;
    const t0 = performance.now();
    selected = index;
    const c = cycles[index];
    for (const node of rendered.values()) node.classList.toggle("selected", Number(node.dataset.index) === index);
    scrollToIndex(index);
    renderSummary(c);
    renderFirings(c);
    renderGoals(c, index);
    renderWM(index);
    renderSide(c);
    if (hasRun) { renderNetwork(index); renderFrame(index); }
    if (!fromVideo) seekVideo(index);
    renderLook(index);
    document.body.dataset.selected = String(c.c);
    document.body.dataset.renderMs = (performance.now() - t0).toFixed(1);
    if (history.replaceState) history.replaceState(null, "", "#d=" + c.c);
  }

  resetRows();
  const m = /#d=(\d+)/.exec(location.hash);
  const initial = m && byCycle.has(Number(m[1])) ? byCycle.get(Number(m[1])) : 0;
  if (cycles.length) select(initial);
  else document.getElementById("decision-summary").appendChild(el("div", "empty", "this trace has no decision cycles"));
  timeline.focus();
  document.body.dataset.ready = "1";
})();
