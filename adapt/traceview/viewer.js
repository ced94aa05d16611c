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
  if (f) bits.push(["stopped", f.stop_reason || "?"]);
  else bits.push(["stopped", "no footer (interrupted run?)"]);
  if (h.files && h.files.length) bits.push(["rules", h.files.join(", ")]);
  bits.forEach(([k, v], i) => {
    if (i) summary.appendChild(document.createTextNode("  ·  "));
    summary.appendChild(document.createTextNode(k + " "));
    summary.appendChild(el("b", null, v));
  });
  if (DATA.notices && DATA.notices.length) {
    const n = document.getElementById("notices");
    n.hidden = false;
    n.textContent = DATA.notices.join(" ");
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

  function select(index) {
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
