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

// What tests and users can read: the newest image's sequence number and latency (ms from the
// change to the image decoded on screen), every latency, the last error.
const aq = (window.aq = { seq: 0, shownSeq: 0, latencies: [], lastError: '', connected: false, schema: null, state: null });

let ws = null;
let gui = null;
let header = null;          // the image message whose PNG comes next
let sentAt = new Map();     // seq -> performance.now() when sent
let objectUrl = null;
let state = { target: 'final', frame: 0, view: [0, 0, 1], variants: {}, params: {} };
aq.state = state;

function send(type, wantSchema = false) {
  if (!ws || ws.readyState !== WebSocket.OPEN) return;
  state = aq.state;  // the page's state (tests may replace it)
  const seq = ++aq.seq;
  sentAt.set(seq, performance.now());
  ws.send(JSON.stringify({ type, seq, schema: wantSchema, state }));
}

function render(wantSchema = false) { send('render', wantSchema); }
aq.render = render;

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
    state = { style: v, target: 'final', frame: state.frame, width: state.width, height: state.height, view: state.view, variants: {}, params: {} };
    aq.state = state;
    render(true);
  });
  gui.add(top, 'target', schema.targets).name('shown target').onChange((v) => { state.target = v; render(); });
  gui.add(top, 'frame', 0, 239, 1).name('frame (tremor clock)').onFinishChange((v) => { state.frame = v; render(); });
  gui.add(top, 'width', 16, 4096, 1).onFinishChange((v) => { state.width = v; render(); });
  gui.add(top, 'height', 16, 4096, 1).onFinishChange((v) => { state.height = v; render(); });
  gui.add({ reset: () => { state.view = [0, 0, 1]; render(); } }, 'reset').name('reset camera');
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
      const c = p.kind === 'bool'
        ? folder.add(obj, p.name)
        : folder.add(obj, p.name, p.min, p.max, p.kind === 'int' ? 1 : (p.max - p.min) / 1000);
      c.domElement.title = `${p.doc} (default ${p.default}, range [${p.min}, ${p.max}])`;
      c.domElement.dataset.param = key;
      c.onChange((val) => { state.params[key] = typeof val === 'boolean' ? (val ? 1 : 0) : val; render(); });
    }
  }
  gui.add({ save: () => send('save') }, 'save').name('Save PNG + manifest + state');
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
    aq.shownPng = blob;  // the PNG bytes on screen, as the server sent them
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

// Camera: drag to turn about the scene's centre, wheel to move closer.
let drag = null;
view.addEventListener('mousedown', (e) => { drag = { x: e.clientX, y: e.clientY, v: state.view.slice() }; e.preventDefault(); });
window.addEventListener('mouseup', () => { drag = null; });
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const yaw = drag.v[0] - (e.clientX - drag.x) * 0.4;
  const pitch = Math.max(-89, Math.min(89, drag.v[1] + (e.clientY - drag.y) * 0.4));
  state.view = [Math.round(yaw * 10) / 10, Math.round(pitch * 10) / 10, state.view[2]];
  render();
});
view.addEventListener('wheel', (e) => {
  e.preventDefault();
  const z = Math.max(0.05, Math.min(20, state.view[2] * Math.exp(-e.deltaY * 0.001)));
  state.view = [state.view[0], state.view[1], Math.round(z * 1000) / 1000];
  render();
}, { passive: false });
document.getElementById('save').addEventListener('click', () => send('save'));

connect();
