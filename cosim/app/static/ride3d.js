// ride3d.js: the 3-D ride of a bicycle with three.js (classic script; uses the global THREE of
// vendor/three.min.js). Defines window.CosimRide3D (the interface of notes/app-team.md):
//   createView(canvas, geometry, options?) -> view: setPose(q), setPath(points), render(), frames,
//       resize(width, height), dispose(); also view.pose (the last pose set), view.orbit (the
//       camera: azimuth from the heading, elevation [rad], distance [m]), view.drawnWheels().
//       options: rider (true), follow (true: the camera follows the bicycle), steerAxis (true: the
//       steer axis dashed down to the ground, showing the trail), background, preserveDrawingBuffer.
//       To draw another geometry, dispose() the view and create a new one on the same canvas.
//   createPlayer(view, trajectory, {rate, onFrame, onEnd}) -> player: play, pause, seek, setRate, state
//   poseAt(trajectory, t) -> q (linear interpolation, exact at the sample times)
//   kinematics(geometry, q) -> the points and rotations of the drawn bicycle (Meijaard axes)
//   frontContactHeight(geometry, q) -> height [m] of the lowest point of the front wheel above the ground
//   lowestPoint(centre, axle, r, t) -> the lowest point of a toroidal wheel; view.drawnWheels(): the
//       wheels as the scene graph draws them (tests check them against kinematics() and the FMU)
//
// Frames and signs. The bicycle's configuration is Meijaard et al. (2007)'s, as in the FMUs
// (Bicycle.Mechanics.Ground): ground axes x forward, y right, z down; the rear frame's
// orientation R = Rz(psi) Rx(phi) Ry(theta) (yaw psi about the ground z, roll phi about the yaw
// frame's x, pitch theta about the roll frame's y, positive nose up); the steer axis (sin lam, 0,
// cos lam) in the rear frame's axes, the front frame turned by delta about it (Rodrigues); the
// wheels turned by thetaR, thetaF about their axles (the hub frames' y). Roll, steer and yaw are
// positive to the right, wheel angles decrease when rolling forward.
// All of the bicycle is built and posed in Meijaard axes inside one group, `meijaard`, whose
// rotation maps them onto three.js's y-up world: the proper rotation Rx(+90 deg),
//   (x, y, z)_Meijaard -> (X, Y, Z)_three = (x, -z, y)    (det = +1),
// so the ground z = 0 is three's Y = 0 plane, up is +Y, forward +X and right +Z.
//
// Kinematics (what kinematics() computes and the meshes follow): rear contact point (x, y, 0);
// rear wheel centre = contact - (rR - tR) Lz - tR ez (Lz: the roll frame's z, down in the rear
// wheel plane; tR the crown radius of the toroidal tyre, 0 = knife edge); steer-axis point (on the
// ground of the nominal configuration) = rear centre + R (w + c, 0, rR); front wheel centre =
// steer point + Rf (-c, 0, -rF) with Rf = R Rot(n, delta); front contact = front centre +
// (rF - tF) e + tF ez, e the unit vector of the front wheel plane pointing most steeply down.
// These are the FMUs' equations (Bicycle.Mechanics.Frames, Bicycle.Wheels.Torus; Meijaard et al.
// 2007, Table 1: the front axle at (w, -rF) and the steer axis through (w + c, 0) of the upright
// bicycle), so the FMU's pitch, which solves the holonomic constraint, puts the drawn front wheel
// on the ground (tests/test_animate.py). Only w, c, lam, rR, rF, tR, tF are data: the frame tubes,
// saddle, handlebar and the rider figure are drawn in proportion to the wheelbase (w / 1.02 m).
(function () {
  "use strict";

  // --- small vector algebra in Meijaard axes (arrays [x, y, z]; 3x3 matrices as [col1, col2, col3]) ---
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function scale(a, k) { return [a[0] * k, a[1] * k, a[2] * k]; }
  function axpy(k, a, b) { return [k * a[0] + b[0], k * a[1] + b[1], k * a[2] + b[2]]; }
  function mulMV(m, v) {  // m = [c1, c2, c3] columns
    return [m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
      m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
      m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2]];
  }
  function mulMM(a, b) { return [mulMV(a, b[0]), mulMV(a, b[1]), mulMV(a, b[2])]; }
  // Rotation by angle about the unit axis n (Rodrigues), as columns: the same formula as
  // Bicycle.Mechanics.Joints.PartialRevolute.
  function rodrigues(n, angle) {
    const c = Math.cos(angle), s = Math.sin(angle), k = 1 - c;
    const [x, y, z] = n;
    return [[c + k * x * x, k * y * x + s * z, k * z * x - s * y],
      [k * x * y - s * z, c + k * y * y, k * z * y + s * x],
      [k * x * z + s * y, k * y * z - s * x, c + k * z * z]];
  }

  function num(value, fallback) {
    return (typeof value === "number" && isFinite(value)) ? value : fallback;
  }

  function checkGeometry(g) {
    if (!g || typeof g !== "object") throw new TypeError("CosimRide3D: geometry must be {w, c, lam, rR, rF, tR?, tF?}");
    for (const key of ["w", "c", "lam", "rR", "rF"]) {
      if (typeof g[key] !== "number" || !isFinite(g[key])) {
        throw new TypeError("CosimRide3D: geometry." + key + " must be a finite number [m or rad], got " + g[key]);
      }
    }
    if (g.w <= 0 || g.rR <= 0 || g.rF <= 0) throw new RangeError("CosimRide3D: geometry w, rR, rF must be positive");
    const tR = num(g.tR, 0), tF = num(g.tF, 0);
    if (tR < 0 || tR > g.rR || tF < 0 || tF > g.rF) throw new RangeError("CosimRide3D: crown radii need 0 <= tR <= rR, 0 <= tF <= rF");
    return { w: g.w, c: g.c, lam: g.lam, rR: g.rR, rF: g.rF, tR: tR, tF: tF };
  }

  function pose(q) {
    q = q || {};
    return { x: num(q.x, 0), y: num(q.y, 0), psi: num(q.psi, 0), phi: num(q.phi, 0), theta: num(q.theta, 0),
      delta: num(q.delta, 0), thetaR: num(q.thetaR, 0), thetaF: num(q.thetaF, 0) };
  }

  /**
   * The drawn bicycle's kinematics in Meijaard's ground axes (x forward, y right, z down) [m].
   * @param {object} geometry {w, c, lam, rR, rF, tR?, tF?} [m, rad]
   * @param {object} q {x, y, psi, phi, theta?, delta, thetaR?, thetaF?} [m, rad]; missing -> 0
   * @returns {{R, Rf, rearContact, rearCentre, steerPoint, steerAxis, frontCentre, frontContact}}
   *   R, Rf: the rear and front frames' orientations (columns = their axes in ground axes)
   */
  function kinematics(geometry, q) {
    const g = checkGeometry(geometry), p = pose(q);
    const cps = Math.cos(p.psi), sps = Math.sin(p.psi), cph = Math.cos(p.phi), sph = Math.sin(p.phi);
    const cth = Math.cos(p.theta), sth = Math.sin(p.theta);
    const Ax = [cps, sps, 0], Ay = [-sps, cps, 0], ez = [0, 0, 1];
    const Ly = axpy(cph, Ay, scale(ez, sph)), Lz = axpy(-sph, Ay, scale(ez, cph));
    const R = [axpy(cth, Ax, scale(Lz, -sth)), Ly, axpy(sth, Ax, scale(Lz, cth))];
    const rearContact = [p.x, p.y, 0];
    const rearCentre = axpy(-(g.rR - g.tR), Lz, axpy(-g.tR, ez, rearContact));
    const steerPoint = add(rearCentre, mulMV(R, [g.w + g.c, 0, g.rR]));
    const axisLocal = [Math.sin(g.lam), 0, Math.cos(g.lam)];
    const Rf = mulMM(R, rodrigues(axisLocal, p.delta));
    const frontCentre = add(steerPoint, mulMV(Rf, [-g.c, 0, -g.rF]));
    const frontContact = lowestPoint(frontCentre, Rf[1], g.rF, g.tF);
    return { R: R, Rf: Rf, rearContact: rearContact, rearCentre: rearCentre, steerPoint: steerPoint,
      steerAxis: mulMV(R, axisLocal), frontCentre: frontCentre, frontContact: frontContact };
  }

  /** The lowest point of a toroidal wheel (radius r, crown radius t; t = 0: knife edge) with the
   *  centre and the axle (unit vector) given in Meijaard axes: centre + (r - t) e + t ez, e the unit
   *  vector of the wheel plane pointing most steeply down (Bicycle.Wheels.Torus). */
  function lowestPoint(centre, axle, r, t) {
    const s = axle[2], cs = Math.sqrt(Math.max(0, 1 - s * s));
    const e = cs > 1e-12 ? [-s * axle[0] / cs, -s * axle[1] / cs, cs] : [0, 0, 1];
    return axpy(r - t, e, axpy(t, [0, 0, 1], centre));
  }

  /** Height [m] above the ground of the lowest point of the front wheel (tyre) in the pose q;
   *  0 when the front wheel touches the ground (the holonomic constraint of the Whipple model). */
  function frontContactHeight(geometry, q) {
    return -kinematics(geometry, q).frontContact[2];
  }

  // --- trajectories -----------------------------------------------------------------------
  const POSE_KEYS = ["x", "y", "psi", "phi", "theta", "delta", "thetaR", "thetaF"];

  function checkTrajectory(tr) {
    if (!tr || !tr.t || typeof tr.t.length !== "number" || tr.t.length < 1) {
      throw new TypeError("CosimRide3D: trajectory.t must be a non-empty array of times [s]");
    }
    const n = tr.t.length;
    for (const key of POSE_KEYS) {
      if (tr[key] != null && tr[key].length !== n) {
        throw new RangeError("CosimRide3D: trajectory." + key + " has " + tr[key].length + " samples, t has " + n);
      }
    }
    for (let i = 1; i < n; i++) {
      if (!(tr.t[i] >= tr.t[i - 1])) throw new RangeError("CosimRide3D: trajectory.t decreases at sample " + i);
    }
  }

  /** Index i of the last sample with t[i] <= time (0 before the start). */
  function sampleIndex(t, time) {
    let lo = 0, hi = t.length - 1;
    if (time >= t[hi]) return hi;
    if (time <= t[0]) return 0;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (t[mid] <= time) lo = mid; else hi = mid;
    }
    return lo;
  }

  /** The pose at time t [s]: linear interpolation between the samples, exact at the sample times,
   *  clamped to the first/last sample outside; missing signals -> 0. */
  function poseAt(trajectory, time) {
    const t = trajectory.t, i = sampleIndex(t, time), n = t.length;
    const j = Math.min(i + 1, n - 1), span = t[j] - t[i];
    const f = (j > i && span > 0 && time > t[i]) ? Math.min(1, (time - t[i]) / span) : 0;
    const q = {};
    for (const key of POSE_KEYS) {
      const a = trajectory[key];
      q[key] = a ? (f === 0 ? a[i] : a[i] + f * (a[j] - a[i])) : 0;
    }
    return q;
  }

  // --- the view ---------------------------------------------------------------------------
  // three.js world point of a Meijaard point (the rotation of the `meijaard` group)
  function toThree(p) { return new THREE.Vector3(p[0], -p[2], p[1]); }

  function createView(canvas, geometry, options) {
    if (typeof THREE === "undefined") throw new Error("CosimRide3D needs three.js (the global THREE)");
    const g = checkGeometry(geometry);
    const UP = new THREE.Vector3(0, 1, 0);
    const opts = Object.assign({ rider: true, follow: true, steerAxis: true, background: 0xdfe9f3 }, options || {});
    const s = g.w / 1.02;  // size of the frame tubes and the rider relative to the benchmark bicycle
    let renderer;
    try {
      renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true,
        preserveDrawingBuffer: !!opts.preserveDrawingBuffer });
    } catch (err) {
      throw new Error("CosimRide3D: WebGL is not available in this browser (" + (err && err.message) + ")");
    }
    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(opts.background);
    scene.fog = new THREE.Fog(opts.background, 12, 30);
    const camera = new THREE.PerspectiveCamera(40, 1, 0.05, 400);
    // shadow-free lighting: sky/ground hemisphere and one sun
    scene.add(new THREE.HemisphereLight(0xffffff, 0x6b7a5a, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(-4, 10, -6);
    scene.add(sun);

    const disposables = [];
    function keep(x) { disposables.push(x); return x; }
    const mat = {
      frame: keep(new THREE.MeshLambertMaterial({ color: 0xc0392b })),
      fork: keep(new THREE.MeshLambertMaterial({ color: 0x8e2a20 })),
      metal: keep(new THREE.MeshLambertMaterial({ color: 0x9aa3ab })),
      tyre: keep(new THREE.MeshLambertMaterial({ color: 0x1e1e1e })),
      saddle: keep(new THREE.MeshLambertMaterial({ color: 0x2b2b2b })),
      shirt: keep(new THREE.MeshLambertMaterial({ color: 0x2e6da4 })),
      trousers: keep(new THREE.MeshLambertMaterial({ color: 0x34495e })),
      skin: keep(new THREE.MeshLambertMaterial({ color: 0xe0ac8a })),
      spoke: keep(new THREE.LineBasicMaterial({ color: 0x555555 })),
      path: keep(new THREE.LineBasicMaterial({ color: 0x1f4e9c })),
    };

    // ground: a plane and a 1 m grid (three's XZ plane is Meijaard's ground z = 0)
    const groundGeo = keep(new THREE.PlaneGeometry(400, 400));
    groundGeo.rotateX(-Math.PI / 2);
    const ground = new THREE.Mesh(groundGeo, keep(new THREE.MeshLambertMaterial({ color: 0xb9c7a5 })));
    ground.position.y = -0.002;
    scene.add(ground);
    // of 1 m segments: long lines through the camera's near plane went missing in SwiftShader
    // (headless Chromium), THREE.GridHelper's included; the fog hides the grid's edge
    const gridLines = [], half = 30;
    for (let k = -half; k <= half; k++) {
      for (let m = -half; m < half; m++) gridLines.push(m, 0, k, m + 1, 0, k, k, 0, m, k, 0, m + 1);
    }
    const gridGeo = keep(new THREE.BufferGeometry());
    gridGeo.setAttribute("position", new THREE.Float32BufferAttribute(gridLines, 3));
    const grid = new THREE.LineSegments(gridGeo, keep(new THREE.LineBasicMaterial({ color: 0x6f7f5f })));
    grid.position.y = 0.001;
    scene.add(grid);

    // everything below is in Meijaard axes (see the top of the file)
    const meijaard = new THREE.Group();
    meijaard.rotation.x = Math.PI / 2;
    scene.add(meijaard);

    // tubes: one shared unit cylinder along y, scaled and turned between two points
    const unitTube = keep(new THREE.CylinderGeometry(1, 1, 1, 10));
    const tmp = new THREE.Vector3();
    function setTube(mesh, a, b, radius) {
      const A = a.isVector3 ? a : new THREE.Vector3(a[0], a[1], a[2]);
      const B = b.isVector3 ? b : new THREE.Vector3(b[0], b[1], b[2]);
      tmp.subVectors(B, A);
      const length = tmp.length();
      mesh.position.addVectors(A, B).multiplyScalar(0.5);
      if (length > 1e-9) mesh.quaternion.setFromUnitVectors(UP, tmp.divideScalar(length));
      mesh.scale.set(radius, Math.max(length, 1e-9), radius);
    }
    function tube(parent, a, b, radius, material) {
      const mesh = new THREE.Mesh(unitTube, material);
      setTube(mesh, a, b, radius);
      parent.add(mesh);
      return mesh;
    }
    function ball(parent, p, radius, material) {
      const geo = keep(new THREE.SphereGeometry(radius, 16, 12));
      const mesh = new THREE.Mesh(geo, material);
      mesh.position.set(p[0], p[1], p[2]);
      parent.add(mesh);
      return mesh;
    }

    // a wheel in its hub frame (x-z plane, axle y): toroidal tyre, rim, spokes, hub
    function wheel(r, t) {
      const group = new THREE.Group();
      const tube_ = t > 0 ? t : 0.016 * s;  // knife edge: a thin tyre whose outer radius is r
      const tyre = keep(new THREE.TorusGeometry(r - tube_, tube_, 10, 48));
      tyre.rotateX(Math.PI / 2);  // torus in the x-z plane, its axis along y
      group.add(new THREE.Mesh(tyre, mat.tyre));
      const rimR = r - 2 * tube_;
      const rim = keep(new THREE.TorusGeometry(rimR, 0.006 * s, 6, 48));
      rim.rotateX(Math.PI / 2);
      group.add(new THREE.Mesh(rim, mat.metal));
      const spokes = [], n = 18, hubHalf = 0.035 * s;
      for (let k = 0; k < n; k++) {
        const a = 2 * Math.PI * k / n, side = (k % 2 ? 1 : -1) * hubHalf;
        spokes.push(0, side, 0, rimR * Math.cos(a), 0, rimR * Math.sin(a));
      }
      const spokeGeo = keep(new THREE.BufferGeometry());
      spokeGeo.setAttribute("position", new THREE.Float32BufferAttribute(spokes, 3));
      group.add(new THREE.LineSegments(spokeGeo, mat.spoke));
      // two thick spokes, coloured, so that the wheel's rotation is visible at any speed
      tube(group, [0, 0, 0], [rimR, 0, 0], 0.008 * s, mat.frame);
      tube(group, [0, 0, 0], [-rimR, 0, 0], 0.008 * s, mat.frame);
      tube(group, [0, -hubHalf, 0], [0, hubHalf, 0], 0.02 * s, mat.metal);
      return group;
    }

    // --- rear frame B: origin at the rear axle, Meijaard axes of the frame --------------------
    const rear = new THREE.Group();
    meijaard.add(rear);
    const rR = g.rR, rF = g.rF, w = g.w, c = g.c, tl = Math.tan(g.lam);
    // nominal point (x forward from the rear contact, h above the ground) in the rear frame
    function nom(x, h, y) { return [x, y || 0, rR - h]; }
    function axisX(h) { return w + c - h * tl; }  // the steer axis at height h (nominal)
    const hBB = 0.9 * Math.min(rR, rF), xBB = 0.42 * w;
    const hHead1 = 2 * rF + 0.06 * s, hHead2 = 2 * rF + 0.22 * s;
    const A = nom(0, rR), BB = nom(xBB, hBB);
    const H1 = nom(axisX(hHead1), hHead1), H2 = nom(axisX(hHead2), hHead2);
    const Sad = nom(xBB - 0.24 * s, hBB + 0.68 * s);
    const S0 = [BB[0] + 0.82 * (Sad[0] - BB[0]), 0, BB[2] + 0.82 * (Sad[2] - BB[2])];
    const R_TUBE = 0.018 * s;
    tube(rear, BB, S0, R_TUBE, mat.frame);             // seat tube
    tube(rear, S0, Sad, 0.012 * s, mat.metal);         // seat post
    tube(rear, S0, H2, R_TUBE, mat.frame);             // top tube
    tube(rear, BB, H1, R_TUBE * 1.15, mat.frame);      // down tube
    tube(rear, H1, H2, R_TUBE * 1.4, mat.frame);       // head tube (part of the rear frame)
    for (const side of [-1, 1]) {
      tube(rear, [0, side * 0.05 * s, 0], [BB[0], side * 0.02 * s, BB[2]], 0.01 * s, mat.frame);  // chain stay
      tube(rear, [0, side * 0.05 * s, 0], [S0[0], side * 0.015 * s, S0[2]], 0.01 * s, mat.frame);  // seat stay
    }
    const saddleGeo = keep(new THREE.BoxGeometry(0.24 * s, 0.12 * s, 0.04 * s));
    const saddle = new THREE.Mesh(saddleGeo, mat.saddle);
    saddle.position.set(Sad[0] + 0.03 * s, 0, Sad[2] - 0.02 * s);
    rear.add(saddle);
    // cranks and pedals (fixed: the pedalling is not part of the model)
    const crank = 0.17 * s, pedalR = [BB[0] + crank * 0.8, 0.09 * s, BB[2] + crank * 0.6];
    const pedalL = [BB[0] - crank * 0.8, -0.09 * s, BB[2] - crank * 0.6];
    tube(rear, [BB[0], -0.09 * s, BB[2]], [BB[0], 0.09 * s, BB[2]], 0.012 * s, mat.metal);
    tube(rear, [BB[0], 0.09 * s, BB[2]], pedalR, 0.01 * s, mat.metal);
    tube(rear, [BB[0], -0.09 * s, BB[2]], pedalL, 0.01 * s, mat.metal);
    const rearSpin = wheel(rR, g.tR);
    rear.add(rearSpin);
    if (opts.steerAxis) {
      // the steer axis, dashed, from the ground (nominal configuration) to above the stem: where it
      // meets the ground, the trail c ahead of the front contact point is seen
      const top = 2 * rF + 0.45 * s, axisGeo = keep(new THREE.BufferGeometry());
      axisGeo.setAttribute("position", new THREE.Float32BufferAttribute([w + c, 0, rR, axisX(top), 0, rR - top], 3));
      const axisLine = new THREE.Line(axisGeo, keep(new THREE.LineDashedMaterial({ color: 0x333333, dashSize: 0.04 * s, gapSize: 0.03 * s })));
      axisLine.computeLineDistances();
      rear.add(axisLine);
    }

    // --- front frame H: origin at the steer-axis point, turned by delta about the axis --------
    const front = new THREE.Group();
    front.position.set(w + c, 0, rR);  // the steer-axis point in the rear frame
    rear.add(front);
    const steerAxis = new THREE.Vector3(Math.sin(g.lam), 0, Math.cos(g.lam));
    function fnom(x, h, y) { return [x - (w + c), y || 0, -h]; }
    const axle = fnom(w, rF), hCrown = 2 * rF + 0.03 * s, crown = fnom(axisX(hCrown), hCrown);
    const hStem = 2 * rF + 0.32 * s, stem = fnom(axisX(hStem), hStem);
    for (const side of [-1, 1]) {
      tube(front, [axle[0], side * 0.05 * s, axle[2]], [crown[0], side * 0.05 * s, crown[2]], 0.012 * s, mat.fork);
    }
    tube(front, [crown[0], -0.06 * s, crown[2]], [crown[0], 0.06 * s, crown[2]], 0.016 * s, mat.fork);
    tube(front, crown, stem, 0.014 * s, mat.metal);      // steerer and stem
    const barCentre = [stem[0] - 0.02 * s, 0, stem[2]];
    tube(front, stem, barCentre, 0.013 * s, mat.metal);
    const grips = [[barCentre[0] - 0.05 * s, -0.28 * s, barCentre[2] + 0.01 * s],
      [barCentre[0] - 0.05 * s, 0.28 * s, barCentre[2] + 0.01 * s]];
    for (const grip of grips) tube(front, barCentre, grip, 0.012 * s, mat.saddle);
    const frontSpin = wheel(rF, g.tF);
    frontSpin.position.set(axle[0], 0, axle[2]);
    front.add(frontSpin);

    // --- the rider on the rear frame: torso, head, legs (fixed), arms to the grips (follow the steer)
    const arms = [];
    let shoulders = [];
    if (opts.rider) {
      const hip = [Sad[0] + 0.02 * s, 0, Sad[2] - 0.06 * s], lean = 38 * Math.PI / 180, torso = 0.55 * s;
      const dir = [Math.sin(lean), 0, -Math.cos(lean)];
      const neck = axpy(torso, dir, hip), head = axpy(torso + 0.16 * s, dir, hip);
      const chest = tube(rear, hip, neck, 0.11 * s, mat.shirt);
      chest.scale.z *= 1.35;  // wider across the shoulders than deep (the tube's local z is sideways)
      ball(rear, hip, 0.12 * s, mat.trousers);
      ball(rear, head, 0.1 * s, mat.skin);
      shoulders = [[neck[0], -0.19 * s, neck[2]], [neck[0], 0.19 * s, neck[2]]];
      tube(rear, shoulders[0], shoulders[1], 0.055 * s, mat.shirt);
      for (const sh of shoulders) ball(rear, sh, 0.055 * s, mat.shirt);
      for (const grip of grips) ball(front, grip, 0.04 * s, mat.skin);  // the hands
      // legs: thigh and shin of 0.46 s each, the knee forward of the line hip-foot
      const pedals = [pedalL, pedalR], L = 0.46 * s;
      for (let k = 0; k < 2; k++) {
        const side = k ? 1 : -1, h = [hip[0], side * 0.1 * s, hip[2]], f = pedals[k];
        const dx = f[0] - h[0], dz = f[2] - h[2], d = Math.min(Math.hypot(dx, dz), 2 * L * 0.999);
        const m = Math.sqrt(Math.max(L * L - d * d / 4, 0)), ux = dx / Math.hypot(dx, dz), uz = dz / Math.hypot(dx, dz);
        // the perpendicular (uz, -ux) or (-uz, ux): take the one pointing forward (+x)
        const px = uz > 0 ? uz : -uz, pz = uz > 0 ? -ux : ux;
        const knee = [h[0] + ux * d / 2 + px * m, side * 0.1 * s, h[2] + uz * d / 2 + pz * m];
        tube(rear, h, knee, 0.065 * s, mat.trousers);
        tube(rear, knee, f, 0.05 * s, mat.trousers);
        ball(rear, knee, 0.065 * s, mat.trousers);
      }
      for (let k = 0; k < 2; k++) {
        const arm = new THREE.Mesh(unitTube, mat.shirt);
        meijaard.add(arm);
        arms.push(arm);
      }
    }

    // --- the contact path on the ground (Meijaard z slightly negative: just above the ground) --
    let pathCapacity = 0, pathGeo = null;
    const path = new THREE.Line(new THREE.BufferGeometry(), mat.path);
    path.frustumCulled = false;
    meijaard.add(path);
    function setPath(points) {
      const n = points ? points.length : 0;
      if (n > pathCapacity) {
        if (pathGeo) pathGeo.dispose();
        pathCapacity = Math.max(256, 2 * n);
        pathGeo = new THREE.BufferGeometry();
        pathGeo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(3 * pathCapacity), 3));
        path.geometry = pathGeo;
      }
      if (!pathGeo) return;
      const a = pathGeo.attributes.position.array;
      for (let i = 0; i < n; i++) {
        a[3 * i] = points[i][0]; a[3 * i + 1] = points[i][1]; a[3 * i + 2] = -0.004;
      }
      pathGeo.attributes.position.needsUpdate = true;
      pathGeo.setDrawRange(0, n);
    }

    // --- camera: chase/side view following the bicycle; drag to orbit, wheel to zoom ----------
    const orbit = { azimuth: -2.2, elevation: 0.28, distance: 4.2 * s };  // relative to the heading [rad, m]
    let lastPose = pose({}), lastKinematics = null;
    const target0 = kinematics(g, lastPose).rearCentre;
    let drag = null;
    function onDown(ev) { drag = { x: ev.clientX, y: ev.clientY, az: orbit.azimuth, el: orbit.elevation }; canvas.setPointerCapture && canvas.setPointerCapture(ev.pointerId); }
    function onMove(ev) {
      if (!drag) return;
      orbit.azimuth = drag.az + (ev.clientX - drag.x) * 0.008;
      orbit.elevation = Math.min(1.45, Math.max(0.02, drag.el + (ev.clientY - drag.y) * 0.006));
      if (!view.animating) view.render();
    }
    function onUp() { drag = null; }
    function onWheel(ev) {
      ev.preventDefault();
      orbit.distance = Math.min(40 * s, Math.max(1.2 * s, orbit.distance * Math.exp(ev.deltaY * 0.001)));
      if (!view.animating) view.render();
    }
    canvas.addEventListener("pointerdown", onDown);
    canvas.addEventListener("pointermove", onMove);
    canvas.addEventListener("pointerup", onUp);
    canvas.addEventListener("pointercancel", onUp);
    canvas.addEventListener("wheel", onWheel, { passive: false });

    function placeCamera(k) {
      // the target: the middle of the bicycle, at the rider's hip height
      const mid = opts.follow ? scale(add(k.rearContact, k.frontContact), 0.5) : [target0[0] + w / 2, target0[1], 0];
      mid[2] = -0.75 * s;
      const az = (opts.follow ? lastPose.psi : 0) + orbit.azimuth, ce = Math.cos(orbit.elevation);
      const eye = [mid[0] + orbit.distance * ce * Math.cos(az), mid[1] + orbit.distance * ce * Math.sin(az),
        mid[2] - orbit.distance * Math.sin(orbit.elevation)];
      camera.position.copy(toThree(eye));
      camera.up.set(0, 1, 0);
      camera.lookAt(toThree(mid));
      grid.position.set(Math.round(mid[0]), 0.001, Math.round(mid[1]));
      ground.position.x = grid.position.x; ground.position.z = grid.position.z;
    }

    const rotation = new THREE.Matrix4();
    const view = {
      frames: 0,
      pose: null,  // the last pose set (all eight coordinates; tests read it)
      animating: false,  // set by a player while it runs (then drags do not render themselves)
      geometry: g,
      /** The camera relative to the bicycle: azimuth from the heading (pi: from behind, -pi/2: from the
       *  left) [rad], elevation [rad], distance [m]; a drag changes azimuth and elevation, the wheel the distance. */
      orbit: orbit,
      scene: scene, camera: camera, renderer: renderer,
      /** Pose the bicycle: q = {x, y, psi, phi, theta?, delta, thetaR?, thetaF?} [m, rad], Meijaard signs. */
      setPose(q) {
        lastPose = pose(q);
        view.pose = lastPose;
        const k = kinematics(g, lastPose);
        const R = k.R;
        rotation.set(R[0][0], R[1][0], R[2][0], 0, R[0][1], R[1][1], R[2][1], 0, R[0][2], R[1][2], R[2][2], 0, 0, 0, 0, 1);
        rear.quaternion.setFromRotationMatrix(rotation);
        rear.position.set(k.rearCentre[0], k.rearCentre[1], k.rearCentre[2]);
        front.quaternion.setFromAxisAngle(steerAxis, lastPose.delta);
        rearSpin.rotation.set(0, lastPose.thetaR, 0);
        frontSpin.rotation.set(0, lastPose.thetaF, 0);
        if (arms.length) {
          rear.updateMatrixWorld(true);
          meijaard.updateMatrixWorld(true);
          const inv = new THREE.Matrix4().copy(meijaard.matrixWorld).invert();
          for (let i = 0; i < 2; i++) {
            const a = rear.localToWorld(new THREE.Vector3(...shoulders[i])).applyMatrix4(inv);
            const b = front.localToWorld(new THREE.Vector3(...grips[i])).applyMatrix4(inv);
            setTube(arms[i], a, b, 0.045 * s);
          }
        }
        lastKinematics = k;
      },
      /** The wheels as drawn (read back from the scene graph, not from kinematics()): centre and
       *  axle (unit vector) of each in Meijaard axes [m], and the lowest point of each tyre. */
      drawnWheels() {
        scene.updateMatrixWorld(true);
        const out = {};
        for (const [name, spin, r, t] of [["rear", rearSpin, g.rR, g.tR], ["front", frontSpin, g.rF, g.tF]]) {
          const c = spin.getWorldPosition(new THREE.Vector3());
          const a = new THREE.Vector3(0, 1, 0).transformDirection(spin.matrixWorld);
          const centre = [c.x, c.z, -c.y], axle = [a.x, a.z, -a.y];  // three -> Meijaard axes
          out[name] = { centre: centre, axle: axle, lowest: lowestPoint(centre, axle, r, t) };
        }
        return out;
      },
      /** The rear contact path [[x, y], ...] [m] drawn on the ground. */
      setPath: setPath,
      /** Draw one frame (view.frames counts them). */
      render() {
        placeCamera(lastKinematics);  // here, so that a drag of the paused view moves the camera
        renderer.render(scene, camera);
        view.frames += 1;
      },
      /** The drawing size in CSS pixels. */
      resize(width, height) {
        renderer.setSize(width, height, false);
        camera.aspect = width / Math.max(1, height);
        camera.updateProjectionMatrix();
      },
      dispose() {
        canvas.removeEventListener("pointerdown", onDown);
        canvas.removeEventListener("pointermove", onMove);
        canvas.removeEventListener("pointerup", onUp);
        canvas.removeEventListener("pointercancel", onUp);
        canvas.removeEventListener("wheel", onWheel);
        for (const d of disposables) d.dispose();
        if (pathGeo) pathGeo.dispose();
        renderer.dispose();
      },
    };
    view.resize(canvas.clientWidth || canvas.width || 640, canvas.clientHeight || canvas.height || 400);
    view.setPose(lastPose);
    return view;
  }

  // --- the player -------------------------------------------------------------------------
  function createPlayer(view, trajectory, options) {
    checkTrajectory(trajectory);
    const opts = Object.assign({ rate: 1 }, options || {});
    const t = trajectory.t, n = t.length, t0 = t[0], tEnd = t[n - 1];
    const hasPath = trajectory.x != null || trajectory.y != null;
    const points = [];
    for (let i = 0; i < n; i++) points.push([trajectory.x ? trajectory.x[i] : 0, trajectory.y ? trajectory.y[i] : 0]);
    const shown = [];
    let rate = +opts.rate > 0 ? +opts.rate : 1, raf = null, last = null;
    const state = { time: t0, playing: false, finished: false };
    Object.defineProperty(state, "frames", { get: () => view.frames, enumerable: true });

    function draw() {
      const q = poseAt(trajectory, state.time);
      view.setPose(q);
      if (hasPath) {
        // the path grows with the time: the samples passed, then the current (interpolated) point
        const i = sampleIndex(t, state.time);
        shown.length = 0;
        for (let k = 0; k <= i; k++) shown.push(points[k]);
        if (state.time > t[i]) shown.push([q.x, q.y]);
        view.setPath(shown);
      }
      view.render();
      if (opts.onFrame) opts.onFrame(state.time);
    }
    function tick(now) {
      raf = null;
      if (!state.playing) return;
      if (last !== null) state.time = Math.min(tEnd, state.time + Math.min(0.1, (now - last) / 1000) * rate);
      last = now;
      draw();
      if (state.time >= tEnd) {
        state.playing = false;
        state.finished = true;
        view.animating = false;
        if (opts.onEnd) opts.onEnd();
        return;
      }
      raf = requestAnimationFrame(tick);
    }
    const player = {
      state: state,
      trajectory: trajectory,
      duration: tEnd - t0,
      /** Play from the current time (from the start once finished). */
      play() {
        if (state.playing) return;
        if (state.finished || state.time >= tEnd) { state.time = t0; state.finished = false; }
        state.playing = true;
        view.animating = true;
        last = null;
        raf = requestAnimationFrame(tick);
      },
      pause() {
        state.playing = false;
        view.animating = false;
        if (raf !== null) cancelAnimationFrame(raf);
        raf = null;
      },
      /** Show the time t [s] (clamped to the trajectory). */
      seek(time) {
        if (!isFinite(+time)) throw new RangeError("CosimRide3D: seek needs a time [s], got " + time);
        state.time = Math.min(tEnd, Math.max(t0, +time));
        state.finished = false;
        last = null;
        draw();
      },
      /** Simulated seconds per real second. */
      setRate(r) {
        if (!(+r > 0)) throw new RangeError("CosimRide3D: the rate must be positive, got " + r);
        rate = +r;
      },
      get rate() { return rate; },
    };
    draw();
    return player;
  }

  window.CosimRide3D = { createView: createView, createPlayer: createPlayer, poseAt: poseAt,
    kinematics: kinematics, frontContactHeight: frontContactHeight, lowestPoint: lowestPoint };
})();
