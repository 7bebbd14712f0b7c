// hapstate-view's page: draws what /api/scene describes and asks /api/move for the force and the
// displacements at each probe position (the server's C++ haptic cursor; nothing is interpolated
// here). ?probe=x,y,z moves the probe there from rest on load.
"use strict";

const el = (id) => document.getElementById(id);
const fmt = (x, digits = 4) => (x === 0 ? "0" : x.toPrecision(digits));

async function getJson(url) {
  const r = await fetch(url);
  const body = await r.json();
  if (!r.ok) throw new Error(body.error || r.statusText);
  return body;
}

// Colour ramp from blue (0) through green to red (1).
function ramp(t, out, i) {
  t = Math.min(1, Math.max(0, t));
  const c = new THREE.Color().setHSL((1 - t) * 0.66, 0.85, 0.5);
  out[3 * i] = c.r; out[3 * i + 1] = c.g; out[3 * i + 2] = c.b;
}

async function main() {
  const scene = await getJson("api/scene");
  el("state").textContent = scene.state;
  const rest = new Float32Array(scene.rest_positions);
  const nView = rest.length / 3;

  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  el("view").appendChild(renderer.domElement);
  const world = new THREE.Scene();
  world.background = new THREE.Color(0x1d2027);
  world.add(new THREE.HemisphereLight(0xffffff, 0x404050, 0.9));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  world.add(sun);

  // The surface: positions updated from the cursor's displacements, coloured by |u|.
  const geometry = new THREE.BufferGeometry();
  const positions = new Float32Array(rest);
  const colours = new Float32Array(3 * nView);
  for (let i = 0; i < nView; ++i) ramp(0, colours, i);
  geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(colours, 3));
  geometry.setIndex(scene.triangles);
  geometry.computeVertexNormals();
  geometry.computeBoundingSphere();
  const surface = new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({
    vertexColors: THREE.VertexColors, side: THREE.DoubleSide, shininess: 20 }));
  world.add(surface);
  world.add(new THREE.LineSegments(new THREE.WireframeGeometry(geometry),
    new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.15 })));

  // The workspace grid: its box, the stored check-points, the refined cells.
  const g = scene.grid;
  const lo = g.lo.map((l, a) => g.origin[a] + l * g.spacing[a]);
  const hi = g.lo.map((l, a) => g.origin[a] + (l + g.dims[a] - 1) * g.spacing[a]);
  const box = new THREE.Box3(new THREE.Vector3(...lo), new THREE.Vector3(...hi));
  world.add(new THREE.Box3Helper(box, 0x8888aa));
  const cp = scene.checkpoints;
  const cpGeometry = new THREE.BufferGeometry();
  cpGeometry.setAttribute("position", new THREE.Float32BufferAttribute(cp.position, 3));
  const cpColours = new Float32Array(cp.levels.length * 3);
  cpGeometry.setAttribute("color", new THREE.BufferAttribute(cpColours, 3));
  const minSpacing = Math.min(...g.spacing);
  world.add(new THREE.Points(cpGeometry, new THREE.PointsMaterial({
    size: 0.25 * minSpacing, vertexColors: THREE.VertexColors })));
  function colourCheckpoints() {
    const byForce = el("colour").value === "force";
    const values = byForce ? cp.force : cp.levels;
    const top = Math.max(1e-30, ...values);
    const bottom = byForce ? 0 : 1;
    for (let i = 0; i < values.length; ++i)
      ramp(top > bottom ? (values[i] - bottom) / (top - bottom) : 0, cpColours, i);
    cpGeometry.attributes.color.needsUpdate = true;
    el("legend").textContent = byForce
      ? `check-points: stored |force| 0 (blue) .. ${fmt(top)} N (red)`
      : `check-points: 1 (blue) .. ${top} (red) levels`;
  }
  el("colour").addEventListener("change", colourCheckpoints);
  colourCheckpoints();
  for (let i = 0; i < scene.refined_cells.length; i += 3) {
    const c = scene.refined_cells.slice(i, i + 3);
    const cell = new THREE.Box3(new THREE.Vector3(...c),
      new THREE.Vector3(c[0] + g.spacing[0], c[1] + g.spacing[1], c[2] + g.spacing[2]));
    world.add(new THREE.Box3Helper(cell, 0xff9933));
  }
  // The certificate's worst errors: red crosses where the probe was, and the headline.
  const cert = scene.certificate;
  if (cert) {
    const h = cert.force_error.hermite, t = cert.force_error.trilinear;
    el("certificate").textContent =
      `certificate${cert.stale ? " (STALE: run hapstate-certify)" : ""}: ${cert.paths} paths, ` +
      `force error worst Hermite ${fmt(100 * h.worst, 3)} %, trilinear ${fmt(100 * t.worst, 3)} %` +
      "; the worst places are red squares";
    const marks = [];
    for (const w of cert.worst) marks.push(...w.probe);
    const markGeometry = new THREE.BufferGeometry();
    markGeometry.setAttribute("position", new THREE.Float32BufferAttribute(marks, 3));
    world.add(new THREE.Points(markGeometry, new THREE.PointsMaterial({
      size: 0.5 * Math.min(...scene.grid.spacing), color: 0xff2020, depthTest: false })));
  }

  // The probe and the force arrow.
  const probeRadius = scene.contact ? scene.probe_radius : 0.3 * minSpacing;
  const probe = new THREE.Mesh(new THREE.SphereGeometry(probeRadius, 24, 16),
    new THREE.MeshPhongMaterial({ color: 0xffd24a, transparent: scene.contact, opacity: 0.55 }));
  probe.position.set(...scene.probe_rest);
  world.add(probe);
  const radius = geometry.boundingSphere.radius;
  const forceScale = Math.max(1e-30, ...cp.force);
  const arrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), probe.position, radius, 0xff4040);
  arrow.visible = false;
  for (const part of [arrow.line, arrow.cone]) part.material.depthTest = false;  // drawn on top
  arrow.renderOrder = 1;
  world.add(arrow);

  const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight,
                                             radius / 100, radius * 100);
  const centre = geometry.boundingSphere.center;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, -1.6, 1.2).multiplyScalar(radius * 1.3));
  camera.up.set(0, 0, 1);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();

  function render() {
    sun.position.copy(camera.position);
    renderer.render(world, camera);
  }
  controls.addEventListener("change", render);
  window.addEventListener("resize", () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    render();
  });

  function show(state) {
    const u = new Float32Array(Uint8Array.from(atob(state.displacements), (c) => c.charCodeAt(0)).buffer);
    let umax = 0;
    for (let i = 0; i < nView; ++i) {
      const d = Math.hypot(u[3 * i], u[3 * i + 1], u[3 * i + 2]);
      umax = Math.max(umax, d);
    }
    for (let i = 0; i < 3 * nView; ++i) positions[i] = rest[i] + u[i];
    for (let i = 0; i < nView; ++i)
      ramp(umax > 0 ? Math.hypot(u[3 * i], u[3 * i + 1], u[3 * i + 2]) / umax : 0, colours, i);
    geometry.attributes.position.needsUpdate = true;
    geometry.attributes.color.needsUpdate = true;
    geometry.computeVertexNormals();
    probe.position.set(...state.probe);
    const f = new THREE.Vector3(...state.force);
    const norm = f.length();
    arrow.position.copy(probe.position);
    if (norm > 0) {
      arrow.setDirection(f.clone().normalize());
      // 0.15 of the body's radius for a small force, 0.5 for the largest stored one.
      const length = (0.15 + 0.35 * Math.min(1, norm / forceScale)) * radius;
      arrow.setLength(length, 0.2 * length, 0.1 * length);
    }
    arrow.visible = norm > 0;
    el("force").textContent = state.force.map((x) => fmt(x, 6)).join(" ");
    el("force-norm").textContent = fmt(norm);
    el("probe").textContent = state.probe.map((x) => fmt(x)).join(", ");
    el("error").textContent = "";
    render();
  }

  // One request in flight; the newest wish is sent when it returns.
  let busy = false, wish = null;
  async function moveTo(target, fromRest) {
    wish = { target, fromRest: fromRest || (wish && wish.fromRest) };
    if (busy) return;
    busy = true;
    while (wish) {
      const w = wish;
      wish = null;
      const q = `api/move?to=${w.target.join(",")}&scheme=${el("scheme").value}` +
                (w.fromRest ? "&from=rest" : "");
      try { show(await getJson(q)); } catch (e) { el("error").textContent = String(e.message); }
    }
    busy = false;
  }
  el("scheme").addEventListener("change", () => moveTo(probe.position.toArray(), false));

  // Dragging the probe: in the plane through it facing the camera.
  const ray = new THREE.Raycaster();
  const plane = new THREE.Plane();
  let dragging = false;
  function pointerRay(event) {
    const r = renderer.domElement.getBoundingClientRect();
    ray.setFromCamera(new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1,
                                        -((event.clientY - r.top) / r.height) * 2 + 1), camera);
  }
  renderer.domElement.addEventListener("pointerdown", (event) => {
    if (event.button !== 0) return;
    pointerRay(event);
    if (!event.shiftKey && ray.intersectObject(probe).length === 0) return;
    dragging = true;
    controls.enabled = false;
    plane.setFromNormalAndCoplanarPoint(camera.getWorldDirection(new THREE.Vector3()), probe.position);
  });
  window.addEventListener("pointermove", (event) => {
    if (!dragging) return;
    pointerRay(event);
    const hit = new THREE.Vector3();
    if (ray.ray.intersectPlane(plane, hit)) moveTo(hit.toArray(), false);
  });
  window.addEventListener("pointerup", () => { dragging = false; controls.enabled = true; });
  window.addEventListener("keydown", (event) => {
    const k = event.key.toLowerCase();
    if (k === "r") return moveTo(scene.probe_rest, true);
    if (k !== "w" && k !== "s") return;
    const d = camera.getWorldDirection(new THREE.Vector3()).multiplyScalar(
      (k === "w" ? 0.25 : -0.25) * minSpacing);
    moveTo(probe.position.clone().add(d).toArray(), false);
  });

  const requested = new URLSearchParams(window.location.search).get("probe");
  if (requested) await moveTo(requested.split(",").map(Number), true);
  else render();
  document.body.dataset.ready = "1";
}

main().catch((e) => {
  el("error").textContent = "hapstate-view: " + e.message;
  document.body.dataset.ready = "error";
});
