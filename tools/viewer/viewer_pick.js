// s3m semantic map viewer, part 3 of 3 (after viewer_voxels.js and viewer.js): picking a voxel
// under the mouse, the voxel's table, framing an object instance, and the "#selftest" mode that
// drives the real UI for tests/browser/viewer_browser_test.cpp. Methods of S3MViewer.Viewer.
(function () {
  "use strict";

  const Viewer = window.S3MViewer.Viewer;

  // ---- picking: the first visible voxel along the click's ray (3-D DDA over the voxel keys) -----
  Viewer.prototype.voxelIndex = function () {
    if (this.keyIndex) return this.keyIndex;
    const v = this.v, m = new Map();
    for (let i = 0; i < v.n; ++i) m.set(v.kx[i] + 65536 * (v.ky[i] + 65536 * v.kz[i]), i);
    return (this.keyIndex = m);
  };

  // Ray (map frame) through canvas pixel (px, py) in CSS pixels relative to the canvas.
  Viewer.prototype.rayAt = function (px, py) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((px / rect.width) * 2 - 1, -(py / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    const inv = new THREE.Matrix4().getInverse(this.world.matrixWorld);
    return new THREE.Ray(ray.ray.origin.clone().applyMatrix4(inv), ray.ray.direction.clone().transformDirection(inv));
  };

  Viewer.prototype.pick = function (ray) {
    const d = this.data, res = d.resolution_m, off = d.key_offset, index = this.voxelIndex();
    const lo = new THREE.Vector3().fromArray(this.boxLo).subScalar(res), hi = new THREE.Vector3().fromArray(this.boxHi).addScalar(res);
    const start = ray.intersectBox(new THREE.Box3(lo, hi), new THREE.Vector3());
    if (!start) return -1;
    const o = ray.origin.distanceTo(start) > 0 ? start : ray.origin.clone();
    const p = [o.x / res, o.y / res, o.z / res], dir = [ray.direction.x, ray.direction.y, ray.direction.z];
    const cell = p.map(Math.floor), step = dir.map(Math.sign);
    const tMax = [0, 1, 2].map(function (a) { return dir[a] ? ((cell[a] + (step[a] > 0)) - p[a]) / dir[a] : Infinity; });
    const tDelta = [0, 1, 2].map(function (a) { return dir[a] ? Math.abs(1 / dir[a]) : Infinity; });
    const limit = 3 * Math.ceil(Math.max(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z) / res) + 3;
    for (let s = 0; s < limit; ++s) {
      const i = index.get((cell[0] + off) + 65536 * ((cell[1] + off) + 65536 * (cell[2] + off)));
      if (i !== undefined && this.isVisible(i)) return i;
      const a = tMax[0] < tMax[1] ? (tMax[0] < tMax[2] ? 0 : 2) : (tMax[1] < tMax[2] ? 1 : 2);
      cell[a] += step[a];
      tMax[a] += tDelta[a];
    }
    return -1;
  };

  Viewer.prototype.pickAt = function (clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const i = this.pick(this.rayAt(clientX - rect.left, clientY - rect.top));
    this.picked = i;
    this.showVoxel(i);
    return i;
  };

  Viewer.prototype.voxelSummary = function (i) {
    const v = this.v, labels = [];
    for (let j = 0; j < v.k; ++j) {
      const id = v.label[i * v.k + j], p = v.prob[i * v.k + j] / 255;
      if (p > 0) labels.push({id: id, name: (this.classes[id] || {name: "class " + id}).name, p: p});
    }
    return {index: i, class_id: v.label[i * v.k], class: (this.classes[v.label[i * v.k]] || {name: "?"}).name,
            key: [v.kx[i], v.ky[i], v.kz[i]], centre_m: [v.pos[3 * i], v.pos[3 * i + 1], v.pos[3 * i + 2]],
            labels: labels, occupancy: v.occ[i] / 255, rgb: [v.rgb[3 * i], v.rgb[3 * i + 1], v.rgb[3 * i + 2]]};
  };

  Viewer.prototype.showVoxel = function (i) {
    const info = this.info;
    info.textContent = "";
    if (i < 0) { info.textContent = "no visible voxel there"; return; }
    const s = this.voxelSummary(i), self = this;
    const t = this.el("table", "", "", info);
    function row(k, val) { const tr = self.el("tr", "", "", t); self.el("th", "", k, tr); self.el("td", "", val, tr); }
    row("class", s.class);
    s.labels.forEach(function (l, j) { row("label " + (j + 1), l.name + "  p=" + l.p.toFixed(3)); });
    row("occupancy", s.occupancy.toFixed(3));
    row("centre [m]", s.centre_m.map(function (x) { return x.toFixed(3); }).join(", "));
    row("colour", "rgb(" + s.rgb.join(", ") + ")");
    row("fusions", this.data.fusions_stored ? "" : "not stored in the map");
    info.dataset.classId = s.class_id;
    info.dataset.key = s.key.join(",");
  };

  // Frames an object instance: orbit target at its centroid, distance from its bounding box.
  Viewer.prototype.frameObject = function (o) {
    const q = this.world.quaternion;
    const c = new THREE.Vector3().fromArray(o.centroid).applyQuaternion(q);
    const ext = new THREE.Vector3().fromArray(o.bbox_max).sub(new THREE.Vector3().fromArray(o.bbox_min)).length();
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    this.controls.target.copy(c);
    this.camera.position.copy(c).add(dir.multiplyScalar(Math.max(ext * 1.8, 0.5)));
    if (this.highlight) this.world.remove(this.highlight);
    const box = new THREE.Box3(new THREE.Vector3().fromArray(o.bbox_min), new THREE.Vector3().fromArray(o.bbox_max));
    box.expandByScalar(this.data.resolution_m / 2);
    this.highlight = new THREE.Box3Helper(box, 0x000000);
    this.world.add(this.highlight);
    this.controls.update();
    this.render();
  };

  // ---- self-test: real DOM events on the real UI, result as JSON in the page ------------------
  Viewer.prototype.selfTest = function () {
    const r = {loaded: true, voxels: this.v.n, drawn: this.drawnCount, faces_in_buffers: this.facesInBuffers,
               faces_drawn: this.facesDrawn, faces_exposed: this.facesExposed, load_ms: this.loadMs};
    const rect = this.renderer.domElement.getBoundingClientRect();
    r.canvas = {x: rect.left + window.scrollX, y: rect.top + window.scrollY, width: rect.width, height: rect.height};
    // Hide the most frequent class through its legend checkbox, count, show it again.
    const ids = Object.keys(this.counts).map(Number).sort((a, b) => this.counts[b] - this.counts[a]);
    if (ids.length) {
      const id = ids[0], box = this.legendInputs[id];
      box.click();
      r.hide = {class_id: id, class_voxels: this.counts[id], drawn_after_hide: this.drawnCount,
                faces_in_buffers: this.facesInBuffers, faces_drawn: this.facesDrawn, faces_exposed: this.facesExposed};
      box.click();
      r.hide.drawn_after_show = this.drawnCount;
    }
    // Click the voxel nearest to the camera among those whose centre projects into the canvas.
    const v = this.v, w = this.world.matrixWorld, p = new THREE.Vector3();
    let best = -1, bestDist = Infinity, bx = 0, by = 0;
    for (let i = 0; i < v.n; ++i) {
      p.set(v.pos[3 * i], v.pos[3 * i + 1], v.pos[3 * i + 2]).applyMatrix4(w);
      const dist = p.distanceTo(this.camera.position);
      if (dist >= bestDist) continue;
      p.project(this.camera);
      if (Math.abs(p.x) > 0.9 || Math.abs(p.y) > 0.9 || p.z > 1) continue;
      best = i; bestDist = dist; bx = (p.x + 1) / 2 * rect.width; by = (1 - p.y) / 2 * rect.height;
    }
    if (best >= 0) {
      const expect = this.voxelSummary(best);
      const canvas = this.renderer.domElement, opts = {bubbles: true, clientX: rect.left + bx, clientY: rect.top + by};
      canvas.dispatchEvent(new PointerEvent("pointerdown", opts));
      canvas.dispatchEvent(new MouseEvent("click", opts));
      r.click = {x: bx, y: by, expected_class_id: expect.class_id, expected_key: expect.key.join(","),
                 reported_class_id: this.info.dataset.classId === undefined ? null : Number(this.info.dataset.classId),
                 reported_key: this.info.dataset.key || null, info_text: this.info.textContent};
    }
    let out = document.getElementById("s3m-selftest");
    if (!out) { out = document.createElement("pre"); out.id = "s3m-selftest"; document.body.appendChild(out); }
    out.textContent = JSON.stringify(r);
  };
})();
