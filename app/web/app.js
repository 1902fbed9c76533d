// The page of `aquarelle serve` (docs/serve.md): a panel generated from the server's schema (the
// style's steps, their registered variants and parameters with ranges and docs), the image, mouse
// camera, Save. Every change sends the whole state; the server renders only the newest one.
const { default: GUI } = await import('./lil-gui.esm.min.js' + location.search);

const token = new URLSearchParams(location.search).get('token') || '';
const view = document.getElementById('view');
const status = document.getElementById('status');
const errorBox = document.getElementById('error');
const timing = document.getElementById('timing');
const command = document.getElementById('command');
const saved = document.getElementById('saved');
const notice = document.getElementById('notice');

// What tests and users can read: the newest image's sequence number and latency (ms from the
// change to the image decoded on screen), every latency, the last error.
const aq = (window.aq = { seq: 0, shownSeq: 0, latencies: [], formats: [], lastError: '', notice: '', connected: false, schema: null, state: null });

let ws = null;
let gui = null;
let header = null;          // the image message whose PNG comes next
let sentAt = new Map();     // seq -> performance.now() when sent
let objectUrl = null;
let state = { target: 'final', frame: 0, view: [0, 0, 1, 0, 0], variants: {}, params: {} };
aq.state = state;

function send(type, wantSchema = false, moving = false) {
  if (!ws || ws.readyState !== WebSocket.OPEN) return;
  state = aq.state;  // the page's state (tests may replace it)
  const seq = ++aq.seq;
  sentAt.set(seq, performance.now());
  ws.send(JSON.stringify({ type, seq, schema: wantSchema, moving, state }));
}

// While the view or a slider moves the server may answer with a preview JPEG; when it stops the
// page asks for the same state once more, as the lossless PNG (docs/serve.md).
function render(wantSchema = false) { send('render', wantSchema); }
function renderMoving() { send('render', false, true); }
aq.render = render;
aq.renderMoving = renderMoving;

function showError(msg) {
  aq.lastError = msg;
  errorBox.textContent = msg;
  errorBox.hidden = !msg;
}

function buildPanel(schema) {
  aq.schema = schema;
  if (gui) gui.destroy();
  gui = new GUI({ container: document.getElementById('panel'), title: 'Aquarelle' });
  state.width = state.width || schema.width;
  state.height = state.height || schema.height;
  const top = { style: schema.style, target: state.target, frame: state.frame, width: state.width, height: state.height };
  gui.add(top, 'style', schema.styles).onChange((v) => {
    state = { style: v, target: 'final', frame: state.frame, width: state.width, height: state.height, view: state.view, variants: {}, params: {}, scene: state.scene };
    aq.state = state;
    render(true);
  });
  gui.add(top, 'target', schema.targets).name('shown target').onChange((v) => { state.target = v; render(); });
  gui.add(top, 'frame', 0, 239, 1).name('frame (tremor clock)').onFinishChange((v) => { state.frame = v; render(); });
  gui.add(top, 'width', 16, 4096, 1).onFinishChange((v) => { state.width = v; render(); });
  gui.add(top, 'height', 16, 4096, 1).onFinishChange((v) => { state.height = v; render(); });
  gui.add({ reset: () => { state.view = [0, 0, 1, 0, 0]; render(); } }, 'reset').name('reset camera');
  for (const step of schema.steps) {
    const folder = gui.addFolder(`${step.id} — ${step.stage}`);
    folder.close();
    folder.domElement.title = step.doc;
    if (step.variants.length > 1) {
      const v = { variant: step.variant };
      folder.add(v, 'variant', step.variants.map((x) => x.name)).onChange((val) => {
        state.variants[step.id] = val;
        // Another variant has other parameters: drop this step's, ask for the new schema.
        for (const k of Object.keys(state.params)) if (k.startsWith(step.id + '.')) delete state.params[k];
        render(true);
      });
    }
    for (const p of step.params) {
      const key = `${step.id}.${p.name}`;
      const obj = { [p.name]: p.kind === 'bool' ? p.value !== 0 : p.value };
      // Named values ("border": clamp / mirror) are a list; the value sent stays the number.
      const named = p.names && p.names.length ? Object.fromEntries(p.names.map((n, i) => [n, i])) : null;
      const c = p.kind === 'bool' ? folder.add(obj, p.name)
        : named ? folder.add(obj, p.name, named)
        : folder.add(obj, p.name, p.min, p.max, p.kind === 'int' ? 1 : (p.max - p.min) / 1000);
      c.domElement.title = `${p.doc} (default ${p.default}, range [${p.min}, ${p.max}])`;
      c.domElement.dataset.param = key;
      const value = (val) => (typeof val === 'boolean' ? (val ? 1 : 0) : val);
      if (p.kind === 'bool' || named) c.onChange((val) => { state.params[key] = value(val); render(); });
      else {
        c.onChange((val) => { state.params[key] = value(val); renderMoving(); });
        c.onFinishChange((val) => { state.params[key] = value(val); render(); });
      }
    }
  }
  if (schema.scene && schema.scene.length) buildScenePanel(schema.scene);
  gui.add({ save: () => send('save') }, 'save').name('Save PNG + manifest + state');
}

// The scene file's art direction (render --scene-set): one folder per block or element (a control
// rule, a layer, the foliage, a light), a control per value; state.scene holds the edited ones.
function buildScenePanel(knobs) {
  const top = gui.addFolder('scene file (art direction)');
  top.close();
  const folders = new Map();
  const edited = (state.scene = state.scene || {});
  // After the file was loaded again, edits of values it no longer has are dropped.
  for (const p of Object.keys(edited)) if (!knobs.some((k) => k.pointer === p)) delete edited[p];
  for (const k of knobs) {
    if (!folders.has(k.group)) { const f = top.addFolder(k.group); f.close(); folders.set(k.group, f); }
    const f = folders.get(k.group);
    const value = k.pointer in edited ? edited[k.pointer] : k.value;
    const set = (v) => { edited[k.pointer] = v; render(); };
    const tip = `${k.pointer} in the scene file (render --scene-set ${k.pointer}=…; the file's value ${JSON.stringify(k.value)})`;
    let controls = [];
    if (k.kind === 'color') {
      const obj = { [k.name]: value.slice() };
      controls.push(f.addColor(obj, k.name, 1).onChange((v) => set(v.map((x) => Math.round(x * 10000) / 10000))));
    } else if (k.kind === 'vector') {
      const cur = value.slice();
      value.forEach((x, i) => {
        const obj = { [`${k.name}[${i}]`]: x };
        controls.push(f.add(obj, `${k.name}[${i}]`).onFinishChange((v) => { cur[i] = v; set(cur.slice()); }));
      });
    } else if (k.kind === 'bool') {
      controls.push(f.add({ [k.name]: value }, k.name).onChange(set));
    } else {
      const c = f.add({ [k.name]: value }, k.name);
      if (k.kind === 'integer') c.step(1);
      controls.push(c.onFinishChange(set));
    }
    for (const c of controls) { c.domElement.title = tip; c.domElement.dataset.scene = k.pointer; }
  }
}

function showImage(blob) {
  const h = header;
  header = null;
  const url = URL.createObjectURL(blob);
  view.onload = () => {
    if (objectUrl) URL.revokeObjectURL(objectUrl);
    objectUrl = url;
    if (h && typeof h.seq === 'number' && sentAt.has(h.seq)) {
      const ms = performance.now() - sentAt.get(h.seq);
      aq.latencies.push(ms);
      timing.textContent = `${ms.toFixed(0)} ms to screen (server ${h.server_ms.toFixed(0)} ms)`;
      for (const k of sentAt.keys()) if (k <= h.seq) sentAt.delete(k);
    }
    aq.shownPng = blob;  // the bytes on screen, as the server sent them
    aq.shownFormat = h ? h.format : '';
    aq.formats.push(aq.shownFormat);
    aq.shownSeq = h && typeof h.seq === 'number' ? h.seq : aq.shownSeq;
  };
  view.src = url;
}

function connect() {
  ws = new WebSocket(`ws://${location.host}/ws?token=${encodeURIComponent(token)}`);
  ws.binaryType = 'blob';
  ws.onopen = () => { aq.connected = true; status.textContent = 'connected'; status.className = ''; };
  ws.onmessage = (ev) => {
    if (typeof ev.data !== 'string') { showImage(ev.data); return; }
    const msg = JSON.parse(ev.data);
    if (msg.type === 'image') {
      header = msg;
      showError('');
      aq.notice = msg.notice || '';
      notice.textContent = aq.notice;
      if (msg.schema) buildPanel(msg.schema);
      command.value = msg.command;
    } else if (msg.type === 'error') {
      showError(msg.message);
    } else if (msg.type === 'saved') {
      saved.textContent = `saved ${msg.png} and its manifest`;
    }
  };
  ws.onclose = () => {
    aq.connected = false;
    status.textContent = 'disconnected: the server stopped (start it again and reload the page)';
    status.className = 'down';
  };
}

// Camera: drag to turn about the scene's centre, shift-drag (or the right or middle button) to
// pan, wheel to move closer. The view is [yaw, pitch, zoom, pan x, pan y] (render --view); a pan
// is in half-heights of the view, so the image follows the pointer.
let drag = null;
const round = (x, k) => Math.round(x * k) / k;
const fullView = (v) => (v.length === 5 ? v.slice() : [v[0], v[1], v[2], 0, 0]);
view.addEventListener('contextmenu', (e) => e.preventDefault());
view.addEventListener('mousedown', (e) => {
  drag = { x: e.clientX, y: e.clientY, v: fullView(state.view), pan: e.shiftKey || e.button !== 0 };
  e.preventDefault();
});
window.addEventListener('mouseup', () => {
  if (drag && drag.moved) render();  // the still image, lossless
  drag = null;
});
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const [yaw0, pitch0, zoom, px0, py0] = drag.v;
  if (drag.pan) {
    const half = Math.max(1, view.clientHeight / 2);
    const px = Math.max(-20, Math.min(20, px0 - (e.clientX - drag.x) / half));
    const py = Math.max(-20, Math.min(20, py0 + (e.clientY - drag.y) / half));
    state.view = [yaw0, pitch0, zoom, round(px, 1000), round(py, 1000)];
  } else {
    const yaw = yaw0 - (e.clientX - drag.x) * 0.4;
    const pitch = Math.max(-89, Math.min(89, pitch0 + (e.clientY - drag.y) * 0.4));
    state.view = [round(yaw, 10), round(pitch, 10), zoom, px0, py0];
  }
  drag.moved = true;
  renderMoving();
});
view.addEventListener('wheel', (e) => {
  e.preventDefault();
  const v = fullView(state.view);
  v[2] = round(Math.max(0.05, Math.min(20, v[2] * Math.exp(-e.deltaY * 0.001))), 1000);
  state.view = v;
  renderMoving();
  clearTimeout(wheelStill);
  wheelStill = setTimeout(render, 200);  // the wheel stopped: the still image
}, { passive: false });
let wheelStill = null;
document.getElementById('save').addEventListener('click', () => send('save'));

connect();
