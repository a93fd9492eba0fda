// s3m semantic map viewer, part 1 of 3 (viewer_voxels.js, viewer.js, viewer_pick.js; index.html
// loads them in this order): the voxel buffer of window.S3M_VIEWER_DATA decoded into typed arrays
// (layout: src/s3m/viewer/viewer_data.hpp) and the cube faces every voxel is drawn with.
// Starts the window.S3MViewer namespace the other parts add to.
(function () {
  "use strict";

  // ---- data -------------------------------------------------------------------------------------
  function decodeBase64(b64) {
    const bin = atob(b64);
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) out[i] = bin.charCodeAt(i);
    return out;
  }

  // Typed-array views of the voxel buffer (layout: viewer_data.hpp).
  function decodeVoxels(data) {
    const n = data.count, k = data.k;
    const bytes = decodeBase64(data.voxels_base64);
    if (bytes.length !== n * (6 + 3 * k + 4)) throw new Error("voxel buffer has " + bytes.length + " bytes, expected " + n * (6 + 3 * k + 4));
    const u16 = new Uint16Array(bytes.buffer, 0, (6 * n + 2 * k * n) / 2);
    let o = 6 * n + 2 * k * n;
    const v = {n: n, k: k, kx: u16.subarray(0, n), ky: u16.subarray(n, 2 * n), kz: u16.subarray(2 * n, 3 * n),
               label: u16.subarray(3 * n, 3 * n + k * n)};
    v.prob = bytes.subarray(o, o + k * n); o += k * n;
    v.rgb = bytes.subarray(o, o + 3 * n); o += 3 * n;
    v.occ = bytes.subarray(o, o + n);
    // World centres and heights along "up".
    const res = data.resolution_m, off = data.key_offset, up = data.up;
    v.pos = new Float32Array(3 * n);
    v.height = new Float32Array(n);
    for (let i = 0; i < n; ++i) {
      const x = (v.kx[i] - off + 0.5) * res, y = (v.ky[i] - off + 0.5) * res, z = (v.kz[i] - off + 0.5) * res;
      v.pos[3 * i] = x; v.pos[3 * i + 1] = y; v.pos[3 * i + 2] = z;
      v.height[i] = x * up[0] + y * up[1] + z * up[2];
    }
    return v;
  }

  function classById(data) {
    const m = {};
    data.classes.forEach(function (c) { m[c.id] = c; });
    return m;
  }

  // Cube faces in key-axis order +x -x +y -y +z -z: outward normal n and the corners n + (-u-v),
  // n + (u-v), n + (u+v), n + (-u+v) with u x v = n, so both triangles wind counter-clockwise
  // seen from outside (three.js culls back faces).
  function face(n, u, w) {
    const c = [];
    [[-1, -1], [1, -1], [1, 1], [-1, 1]].forEach(function (s) {
      for (let a = 0; a < 3; ++a) c.push(n[a] + s[0] * u[a] + s[1] * w[a]);
    });
    return {n: n, corners: c};
  }
  const X = [1, 0, 0], Y = [0, 1, 0], Z = [0, 0, 1], NX = [-1, 0, 0], NY = [0, -1, 0], NZ = [0, 0, -1];
  const FACES = [face(X, Y, Z), face(NX, Z, Y), face(Y, Z, X), face(NY, X, Z), face(Z, X, Y), face(NZ, Y, X)];
  const TRIANGLES = [0, 1, 2, 0, 2, 3];  // the two triangles of a face, as corner numbers

  window.S3MViewer = {decodeVoxels: decodeVoxels, classById: classById, FACES: FACES, TRIANGLES: TRIANGLES};
})();
