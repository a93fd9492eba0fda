// s3m semantic map viewer, part 2 of 3: the occupied voxels of a SemanticOcTree as instanced cubes
// (three.js r111, Debian's libjs-three), with a class legend that hides/shows classes, a confidence slider,
// a ceiling cut, the camera trajectory and keyframe frusta, voxel picking and the object instances
// of `s3m query`. Data: window.S3M_VIEWER_DATA written by src/s3m/viewer (format in viewer_data.hpp).
// Works from file:// with no server: everything arrives through <script> tags.
//
// Test mode: a URL hash "#selftest" drives the real UI (DOM events on the legend, a MouseEvent on
// the canvas) once the map is drawn and writes a JSON result into <pre id="s3m-selftest">
// (tests/browser/viewer_browser_test.cpp reads it with chromium --dump-dom).
//
// Parts: viewer_voxels.js (data, cube faces) before this file, viewer_pick.js (picking, the
// object instances view, the self-test) after it; index.html and report.html load all three.
(function () {
  "use strict";

  const S = window.S3MViewer;  // viewer_voxels.js
  const decodeVoxels = S.decodeVoxels, classById = S.classById, FACES = S.FACES, TRIANGLES = S.TRIANGLES;

  // ---- the viewer ---------------------------------------------------------------------------------
  function Viewer(root, data) {
    this.root = root;
    this.data = data;
    this.classes = classById(data);
    this.hidden = {};          // class id -> true when hidden
    this.minConfidence = 0;    // 0..1
    this.colorMode = "class";  // "class" | "rgb"
    const t0 = performance.now();
    this.v = decodeVoxels(data);
    this.timings = {decode_ms: performance.now() - t0};
    this.counts = {};
    for (let i = 0; i < this.v.n; ++i) this.counts[this.v.label[i * this.v.k]] = (this.counts[this.v.label[i * this.v.k]] || 0) + 1;
    const t1 = performance.now();
    this.buildDom();
    this.buildScene();
    const t2 = performance.now();
    this.ceiling = this.maxHeight;
    this.ready = false;
    this.updateVoxels();
    this.ready = true;
    const t3 = performance.now();
    this.render();
    const gl = this.renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));  // waits for the frame
    Object.assign(this.timings, {scene_ms: t2 - t1, faces_ms: t3 - t2, first_frame_ms: performance.now() - t3});
  }

  Viewer.prototype.el = function (tag, cls, text, parent) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    (parent || this.root).appendChild(e);
    return e;
  };

  Viewer.prototype.buildDom = function () {
    const self = this;
    this.root.classList.add("s3m-viewer");
    this.canvasBox = this.el("div", "s3m-canvas-box");
    const side = this.el("div", "s3m-side");
    this.status = this.el("div", "s3m-status", "", side);
    this.status.id = "s3m-viewer-status";
    // Colour mode.
    const mode = this.el("label", "s3m-row", "", side);
    this.rgbToggle = this.el("input", "", undefined, mode);
    this.rgbToggle.type = "checkbox";
    this.rgbToggle.id = "s3m-rgb-toggle";
    mode.appendChild(document.createTextNode(" observed colour (RGB) instead of class"));
    this.rgbToggle.addEventListener("change", function () { self.colorMode = self.rgbToggle.checked ? "rgb" : "class"; self.updateVoxels(); });
    // Confidence slider.
    const conf = this.el("label", "s3m-row", "", side);
    this.confLabel = this.el("span", "", "", conf);
    this.confSlider = this.el("input", "", undefined, conf);
    Object.assign(this.confSlider, {type: "range", min: 0, max: 100, value: 0, id: "s3m-confidence"});
    this.confSlider.addEventListener("input", function () { self.minConfidence = self.confSlider.value / 100; self.updateVoxels(); });
    // Ceiling cut.
    const cut = this.el("label", "s3m-row", "", side);
    this.cutLabel = this.el("span", "", "", cut);
    this.cutSlider = this.el("input", "", undefined, cut);
    Object.assign(this.cutSlider, {type: "range", min: 0, max: 1000, value: 1000, id: "s3m-ceiling"});
    this.cutSlider.addEventListener("input", function () {
      self.ceiling = self.minHeight + (self.maxHeight - self.minHeight) * self.cutSlider.value / 1000 + 1e-6;
      self.updateVoxels();
    });
    // Legend.
    this.el("div", "s3m-head", "Classes (click to hide / show)", side);
    this.legend = this.el("div", "s3m-legend", "", side);
    this.legendInputs = {};
    Object.keys(this.counts).map(Number).sort(function (a, b) { return self.counts[b] - self.counts[a]; }).forEach(function (id) {
      const c = self.classes[id] || {name: "class " + id, rgb: [255, 0, 255]};
      const row = self.el("label", "s3m-legend-row", "", self.legend);
      const box = self.el("input", "", undefined, row);
      box.type = "checkbox";
      box.checked = true;
      box.dataset.classId = id;
      const sw = self.el("span", "s3m-swatch", "", row);
      sw.style.background = "rgb(" + c.rgb.join(",") + ")";
      self.el("span", "s3m-name", c.name, row);
      self.el("span", "s3m-count", self.counts[id].toLocaleString("en"), row);
      box.addEventListener("change", function () { self.hidden[id] = !box.checked; self.updateVoxels(); });
      self.legendInputs[id] = box;
    });
    // Picked voxel.
    this.el("div", "s3m-head", "Voxel under the mouse click", side);
    this.info = this.el("div", "s3m-info", "click a voxel", side);
    this.info.id = "s3m-voxel-info";
    // Object instances.
    this.el("div", "s3m-head", "Objects (as `s3m query --class`; click to frame)", side);
    this.objects = this.el("div", "s3m-objects", "", side);
    this.buildObjectList();
  };

  Viewer.prototype.buildObjectList = function () {
    const self = this, byClass = {};
    (this.data.instances || []).forEach(function (o, i) { (byClass[o.class_id] = byClass[o.class_id] || []).push(i); });
    const ids = Object.keys(byClass).map(Number);
    if (!ids.length) { this.objects.textContent = "none"; return; }
    ids.forEach(function (id) {
      const c = self.classes[id] || {name: "class " + id, rgb: [255, 0, 255]};
      const group = self.el("details", "s3m-object-class", "", self.objects);
      self.el("summary", "", c.name + " (" + byClass[id].length + ")", group);
      byClass[id].forEach(function (idx, j) {
        const o = self.data.instances[idx];
        const b = self.el("button", "s3m-object", c.name + " #" + (j + 1) + ": " + o.voxels + " voxels, " +
                          o.volume_m3.toFixed(3) + " m\u00b3, p=" + o.mean_confidence.toFixed(2), group);
        b.addEventListener("click", function () { self.frameObject(o); });
      });
    });
  };

  Viewer.prototype.buildScene = function () {
    const self = this, d = this.data, v = this.v;
    this.renderer = new THREE.WebGLRenderer({antialias: false, preserveDrawingBuffer: true});
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0xf4f4f4);
    this.canvasBox.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    // The map's frame rotated so that its "up" is three.js's +Y.
    this.world = new THREE.Group();
    this.world.quaternion.setFromUnitVectors(new THREE.Vector3().fromArray(d.up), new THREE.Vector3(0, 1, 0));
    this.scene.add(this.world);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const sun = new THREE.DirectionalLight(0xffffff, 0.6);
    sun.position.set(0.4, 1.0, 0.7);
    this.scene.add(sun);
    // Voxels: the cube faces not covered by a visible neighbour (a surface map's voxels show 1-3
    // of their 6 faces), runs of one colour drawn as one quad (forEachRun), all in one mesh that
    // is rebuilt when a filter changes.
    // Not three.js instancing: Chromium's software WebGL (SwiftShader, what a machine without a
    // GPU gets) drew 387k instanced quads in 5.1 s but the same quads as one mesh in 0.32 s
    // (docs/RESULTS.md). Shading is baked per face direction into the vertex colours.
    this.faceGeometry = new THREE.BufferGeometry();
    this.faceMesh = new THREE.Mesh(this.faceGeometry, new THREE.MeshBasicMaterial({vertexColors: THREE.VertexColors}));
    this.faceMesh.frustumCulled = false;
    this.world.add(this.faceMesh);
    this.faceCapacity = 0;
    this.visible = new Uint8Array(Math.max(v.n, 1));
    this.buildGrid();
    this.shade = this.faceShades();
    // Extent.
    let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    this.minHeight = Infinity; this.maxHeight = -Infinity;
    for (let i = 0; i < v.n; ++i) {
      for (let a = 0; a < 3; ++a) { lo[a] = Math.min(lo[a], v.pos[3 * i + a]); hi[a] = Math.max(hi[a], v.pos[3 * i + a]); }
      this.minHeight = Math.min(this.minHeight, v.height[i]); this.maxHeight = Math.max(this.maxHeight, v.height[i]);
    }
    if (!v.n) { lo = [-1, -1, -1]; hi = [1, 1, 1]; this.minHeight = 0; this.maxHeight = 1; }
    this.boxLo = lo; this.boxHi = hi;
    this.addTrajectory();
    // Camera looking at the map from above one corner.
    const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2).applyQuaternion(this.world.quaternion);
    const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.5);
    this.camera = new THREE.PerspectiveCamera(50, 1, size / 500, size * 20);
    // From the side the camera flew on (the mapped surfaces face it), raised to look down.
    const t = this.data.trajectory || [], side = new THREE.Vector3(0.6, 0, 0.8);
    if (t.length >= 7) {
      const mean = new THREE.Vector3();
      for (let i = 0; i < t.length; i += 7) mean.add(new THREE.Vector3(t[i], t[i + 1], t[i + 2]));
      mean.multiplyScalar(7 / t.length).applyQuaternion(this.world.quaternion).sub(centre).setY(0);
      if (mean.length() > 1e-3) side.copy(mean).normalize().multiplyScalar(1.0);
    }
    this.camera.position.copy(centre).add(side.setY(0.75).multiplyScalar(size));
    this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.copy(centre);
    this.controls.screenSpacePanning = true;
    this.controls.addEventListener("change", function () { self.render(); });
    this.controls.update();
    // Picking: a click without a drag.
    const canvas = this.renderer.domElement;
    let down = null;
    canvas.addEventListener("pointerdown", function (e) { down = [e.clientX, e.clientY]; });
    canvas.addEventListener("click", function (e) {
      if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;  // it was a drag
      self.pickAt(e.clientX, e.clientY);
    });
    window.addEventListener("resize", function () { self.resize(); });
    this.resize();
  };

  // Trajectory as a line, keyframes as small frusta (camera frame: x right, y down, z forward).
  Viewer.prototype.addTrajectory = function () {
    const d = this.data, t = d.trajectory || [], kf = d.keyframes || [];
    if (t.length >= 14) {
      const pts = [];
      for (let i = 0; i < t.length; i += 7) pts.push(new THREE.Vector3(t[i], t[i + 1], t[i + 2]));
      const g = new THREE.BufferGeometry().setFromPoints(pts);
      this.world.add(new THREE.Line(g, new THREE.LineBasicMaterial({color: 0x1f4fd0})));
    }
    if (kf.length) {
      const cam = d.camera, depth = Math.max(d.resolution_m * 3, 0.08);
      const hx = depth * cam.width / (2 * cam.fx), hy = depth * cam.height / (2 * cam.fy);
      const corners = [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]];
      const seg = [];
      const m = new THREE.Matrix4(), q = new THREE.Quaternion(), p = new THREE.Vector3(), one = new THREE.Vector3(1, 1, 1);
      for (let i = 0; i < kf.length; i += 7) {
        m.compose(p.set(kf[i], kf[i + 1], kf[i + 2]), q.set(kf[i + 3], kf[i + 4], kf[i + 5], kf[i + 6]), one);
        const apex = new THREE.Vector3(0, 0, 0).applyMatrix4(m);
        const cs = corners.map(function (c) { return new THREE.Vector3(c[0], c[1], depth).applyMatrix4(m); });
        for (let j = 0; j < 4; ++j) seg.push(apex, cs[j], cs[j], cs[(j + 1) % 4]);
      }
      const g = new THREE.BufferGeometry().setFromPoints(seg);
      this.world.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({color: 0xd03020})));
    }
  };

  Viewer.prototype.isVisible = function (i) {
    const v = this.v;
    return !this.hidden[v.label[i * v.k]] && v.prob[i * v.k] >= this.minConfidence * 255 && v.height[i] <= this.ceiling;
  };

  // Occupancy grid over the map's key box (1 byte per cell): which cells hold a visible voxel.
  Viewer.prototype.buildGrid = function () {
    const v = this.v;
    let lo = [65535, 65535, 65535], hi = [0, 0, 0];
    for (let i = 0; i < v.n; ++i) {
      const k = [v.kx[i], v.ky[i], v.kz[i]];
      for (let a = 0; a < 3; ++a) { if (k[a] < lo[a]) lo[a] = k[a]; if (k[a] > hi[a]) hi[a] = k[a]; }
    }
    // One cell of margin on each side, so neighbours of border voxels need no bounds checks.
    this.gridLo = lo.map(function (x) { return x - 1; });
    this.gridDim = [0, 1, 2].map(function (a) { return Math.max(hi[a] - lo[a] + 3, 1); });
    const cells = this.gridDim[0] * this.gridDim[1] * this.gridDim[2];
    this.grid = v.n && cells <= 128e6 ? new Uint8Array(cells) : null;  // null: every face is drawn
    // Voxel index + 1 per cell (0: none), to merge neighbouring faces; 4 bytes a cell, so only for
    // grids up to 16e6 cells (a 200k-voxel room is ~2e6); larger maps draw one quad per face.
    this.voxelAt = this.grid && cells <= 16e6 ? new Int32Array(cells) : null;
    this.cell = new Int32Array(Math.max(v.n, 1));
    if (!this.grid) return;
    const d = this.gridDim, o = this.gridLo;
    for (let i = 0; i < v.n; ++i) {
      this.cell[i] = (v.kx[i] - o[0]) + d[0] * ((v.ky[i] - o[1]) + d[1] * (v.kz[i] - o[2]));
      if (this.voxelAt) this.voxelAt[this.cell[i]] = i + 1;
    }
  };

  // Vertex buffers for at least n faces (2 triangles, 6 vertices each, not indexed: WebGL checks
  // the range of an index buffer before its first draw, which cost more than the extra vertices);
  // grown x1.25 when a filter exposes more faces than there is room for.
  Viewer.prototype.reserveFaces = function (n) {
    if (n <= this.faceCapacity && this.faceCapacity) return;
    const cap = Math.max(Math.ceil(n * 1.25), 64), g = this.faceGeometry;
    this.facePos = new Float32Array(18 * cap);
    this.faceCol = new Uint8Array(18 * cap);
    g.dispose();  // frees the old GPU buffers
    g.setAttribute("position", new THREE.BufferAttribute(this.facePos, 3).setUsage(THREE.DynamicDrawUsage));
    g.setAttribute("color", new THREE.BufferAttribute(this.faceCol, 3, true).setUsage(THREE.DynamicDrawUsage));
    this.faceCapacity = cap;
  };

  // Brightness of each face direction: ambient + a light from above and one side (map frame).
  Viewer.prototype.faceShades = function () {
    const q = this.world.quaternion, light = new THREE.Vector3(0.35, 1.0, 0.55).normalize();
    return FACES.map(function (f) {
      const n = new THREE.Vector3().fromArray(f.n).applyQuaternion(q);
      return Math.min(1, 0.62 + 0.38 * Math.max(0, n.dot(light)) - 0.1 * Math.max(0, -n.dot(light)));
    });
  };

  Viewer.prototype.voxelColor = function (i) {
    const v = this.v;
    if (this.colorMode === "rgb") return [v.rgb[3 * i], v.rgb[3 * i + 1], v.rgb[3 * i + 2]];
    const cl = this.classes[v.label[i * v.k]];
    return cl ? cl.rgb : [255, 0, 255];
  };

  // Colour identity of voxel i for merging: its class (class colours) or its packed colour.
  Viewer.prototype.colourKey = function (i) {
    const v = this.v;
    return this.colorMode === "rgb" ? (v.rgb[3 * i] << 16) | (v.rgb[3 * i + 1] << 8) | v.rgb[3 * i + 2] : v.label[i * v.k];
  };

  // Calls quad(i, f, len) for every run of exposed faces: the faces f of voxels i, i + 1, ... along
  // the face's first tangent axis (key axis (f / 2 + 1) % 3) that are visible, exposed (no visible
  // neighbour in direction f) and of one colour. A room's faces are mostly walls, floor and ceiling,
  // so runs are long: SwiftShader (Chromium without a GPU) then draws 5-10x fewer triangles. Without
  // voxelAt (very large grids) or without a grid every run is one face.
  Viewer.prototype.forEachRun = function (quad) {
    const v = this.v, grid = this.grid, cell = this.cell, vis = this.visible, at = this.voxelAt, key = this.keys;
    const d = this.gridDim, stride = grid ? [1, d[0], d[0] * d[1]] : null;
    const exposed = function (i, f) { return !grid || !grid[cell[i] + (f & 1 ? -stride[f >> 1] : stride[f >> 1])]; };
    // j continues i's run of face f: visible, exposed, same colour.
    const joins = function (j, i, f) { return j >= 0 && vis[j] && key[j] === key[i] && exposed(j, f); };
    for (let i = 0; i < v.n; ++i) {
      if (!vis[i]) continue;
      for (let f = 0; f < 6; ++f) {
        if (!exposed(i, f)) continue;
        let len = 1;
        if (at) {
          const sb = stride[((f >> 1) + 1) % 3];
          if (joins(at[cell[i] - sb] - 1, i, f)) continue;  // not the first of its run
          while (joins(at[cell[i] + len * sb] - 1, i, f)) ++len;
        }
        quad(i, f, len);
      }
    }
  };

  // Applies the filters: which voxels are visible, which of their faces are exposed, and writes
  // those faces, merged into runs, into the face buffers.
  Viewer.prototype.updateVoxels = function () {
    const v = this.v, grid = this.grid, cell = this.cell, vis = this.visible;
    let n = 0;
    if (grid) grid.fill(0);
    if (!this.keys || this.keys.length !== v.n) this.keys = new Int32Array(v.n);
    for (let i = 0; i < v.n; ++i) {
      vis[i] = this.isVisible(i) ? 1 : 0;
      if (vis[i]) { ++n; if (grid) grid[cell[i]] = 1; }
      this.keys[i] = this.colourKey(i);
    }
    let quads = 0, faces = 0;
    this.forEachRun(function (i, f, len) { ++quads; faces += len; });
    this.reserveFaces(quads);
    const pos = this.facePos, col = this.faceCol, h = this.data.resolution_m / 2, self = this;
    let q = 0;
    this.forEachRun(function (i, f, len) {
      const rgb = self.voxelColor(i), x = v.pos[3 * i], y = v.pos[3 * i + 1], z = v.pos[3 * i + 2];
      const corners = FACES[f].corners, shade = self.shade[f], b = ((f >> 1) + 1) % 3, extra = (len - 1) * 2 * h;
      for (let t = 0; t < 6; ++t) {
        const c = 3 * TRIANGLES[t], o = 18 * q + 3 * t;
        pos[o] = x + h * corners[c]; pos[o + 1] = y + h * corners[c + 1]; pos[o + 2] = z + h * corners[c + 2];
        if (corners[c + b] > 0) pos[o + b] += extra;  // the run's far end
        col[o] = rgb[0] * shade; col[o + 1] = rgb[1] * shade; col[o + 2] = rgb[2] * shade;
      }
      ++q;
    });
    this.faceGeometry.setDrawRange(0, 6 * quads);
    const pa = this.faceGeometry.attributes.position, ca = this.faceGeometry.attributes.color;
    pa.updateRange.count = ca.updateRange.count = 18 * quads;
    pa.needsUpdate = ca.needsUpdate = true;
    this.facesInBuffers = quads;
    this.facesExposed = faces;
    this.visibleCount = n;
    this.confLabel.textContent = "min. confidence " + this.minConfidence.toFixed(2) + " ";
    this.cutLabel.textContent = "ceiling cut " + this.ceiling.toFixed(2) + " m ";
    this.render();
  };

  Viewer.prototype.resize = function () {
    const w = this.canvasBox.clientWidth || 800, h = this.canvasBox.clientHeight || 600;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  };

  Viewer.prototype.render = function () {
    if (!this.renderer) return;
    if (!this.ready) return;  // one first frame, after the scene is complete
    this.renderer.render(this.scene, this.camera);
    // Face quads are the scene's only triangles (2 each): what WebGL was asked to draw.
    this.facesDrawn = this.renderer.info.render.triangles / 2;
    this.drawnCount = this.visibleCount;
    this.status.textContent = this.drawnCount.toLocaleString("en") + " of " + this.v.n.toLocaleString("en") +
      " voxels shown (" + (this.data.resolution_m * 100).toFixed(1) + " cm), " + this.facesExposed.toLocaleString("en") +
      " faces as " + this.facesDrawn.toLocaleString("en") + " quads";
  };


  // ---- entry point ------------------------------------------------------------------------------
  function start(root, data) {
    if (typeof THREE === "undefined" || !THREE.OrbitControls) {
      root.textContent = "The 3-D view needs three.js (Debian: apt-get install libjs-three), then run the report or `s3m view` again.";
      root.classList.add("s3m-missing");
      return null;
    }
    if (!data) { root.textContent = "no map data (map_data.js) found next to this page"; return null; }
    const viewer = new Viewer(root, data);
    viewer.loadMs = performance.now();  // since navigation start: parsing the scripts included
    root.dataset.loaded = "1";
    root.dataset.loadMs = viewer.loadMs.toFixed(1);
    root.dataset.drawn = viewer.drawnCount;
    root.dataset.facesDrawn = viewer.facesDrawn;
    root.dataset.timings = JSON.stringify(viewer.timings);
    window.s3mViewer = viewer;
    if (/selftest/.test(location.hash)) viewer.selfTest();
    return viewer;
  }


  S.Viewer = Viewer;
  S.start = start;
})();
