// The robot of rcb4hv's 3D view (rcb4hv.ui.scene3d.RobotBody): one three.js group per link
// holding its geoms, plus the centre-of-mass marker and the support polygon on the ground.
// set_pose() only rewrites matrices and two small buffers: nothing is re-created per update.
import { THREE } from "nicegui-scene";

const GROUND_LIFT = 0.0005; // ground marks 0.5 mm above the grid, the plane 0.5 mm below it (no z-fighting)

function matrix(m) {
  // a 3x4 row-major transform -> THREE.Matrix4
  return new THREE.Matrix4().set(
    m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11], 0, 0, 0, 1,
  );
}

function setPoints(geometry, points) {
  // a fresh buffer each time: the number of points changes from pose to pose
  geometry.setAttribute("position", new THREE.Float32BufferAttribute(points.flat(), 3));
  geometry.computeBoundingSphere();
}

function groundGrid(size, divisions, per) {
  // segments of ``per`` cells, not lines across the whole ground: a line with an end behind
  // the camera can vanish in software renderers (SwiftShader clips it away whole), and
  // fewer, longer segments are cheaper to draw there than one per cell edge
  const cell = size / divisions;
  const half = size / 2;
  const points = [];
  for (let i = 0; i <= divisions; i++) {
    const a = -half + i * cell;
    for (let j = 0; j < divisions; j += per) {
      const b = -half + j * cell;
      const e = -half + Math.min(j + per, divisions) * cell;
      points.push(a, b, 0, a, e, 0, b, a, 0, e, a, 0);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.Float32BufferAttribute(points, 3));
  return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0xa3afbf }));
}

function sentinel(body) {
  // An empty triangle rendered with every frame: it hides ``body`` while the canvas is not
  // displayed (a page tab in the background), so a hidden view costs a clear, not a scene
  // rasterised in software. The change shows from the next frame on.
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.Float32BufferAttribute(new Array(9).fill(0), 3));
  const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ colorWrite: false, depthWrite: false }));
  mesh.frustumCulled = false;
  mesh.onBeforeRender = (renderer) => {
    body.visible = renderer.domElement.offsetParent !== null;
  };
  return mesh;
}

function geometry(shape, size) {
  if (shape === "box") return new THREE.BoxGeometry(size[0], size[1], size[2]);
  if (shape === "cylinder") {
    // three.js cylinders run along y; the model's along z
    const g = new THREE.CylinderGeometry(size[0], size[0], size[1], 16);
    g.rotateX(Math.PI / 2);
    return g;
  }
  return new THREE.SphereGeometry(size[0], 16, 12);
}

export default class RobotBody {
  create_mesh(links, pose, ground) {
    this.root = new THREE.Group();
    this.body = new THREE.Group(); // everything drawn; hidden while the canvas is not shown
    this.root.add(this.body, sentinel(this.body));
    if (ground) {
      // the ground: a plane and a grid of [size, divisions, cells per segment] in x-y
      const [size, divisions, per] = ground;
      const plane = new THREE.Mesh(
        new THREE.PlaneGeometry(size, size),
        new THREE.MeshPhongMaterial({ color: 0xe2e8f0 }),
      );
      plane.position.z = -GROUND_LIFT;
      const grid = groundGrid(size, divisions, per);
      this.body.add(plane, grid);
    }
    this.links = links.map((geoms) => {
      const group = new THREE.Group();
      group.matrixAutoUpdate = false;
      for (const [shape, size, local, rgba] of geoms) {
        const material = new THREE.MeshPhongMaterial({
          color: new THREE.Color(rgba[0], rgba[1], rgba[2]),
          transparent: rgba[3] < 1,
          opacity: rgba[3],
        });
        const mesh = new THREE.Mesh(geometry(shape, size), material);
        mesh.matrixAutoUpdate = false;
        mesh.matrix.copy(matrix(local));
        group.add(mesh);
      }
      this.body.add(group);
      return group;
    });
    this.com = new THREE.Mesh(
      new THREE.CylinderGeometry(0.008, 0.008, 0.001, 24).rotateX(Math.PI / 2),
      new THREE.MeshBasicMaterial({ color: 0x16a34a }),
    );
    this.plumb = new THREE.Line(
      new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x16a34a }),
    );
    this.outline = new THREE.LineLoop(
      new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x2563eb }),
    );
    this.area = new THREE.Mesh(
      new THREE.BufferGeometry(),
      new THREE.MeshBasicMaterial({ color: 0x60a5fa, transparent: true, opacity: 0.35, side: THREE.DoubleSide }),
    );
    this.body.add(this.com, this.plumb, this.outline, this.area);
    this.apply_pose(pose);
    return this.root;
  }

  set_pose(pose) {
    const started = performance.now();
    this.apply_pose(pose);
    // counters for the browser tests and `make bench` (poses applied, milliseconds spent)
    window.rcb4hvPoses = (window.rcb4hvPoses || 0) + 1;
    window.rcb4hvPoseMs = (window.rcb4hvPoseMs || 0) + (performance.now() - started);
  }

  apply_pose(pose) {
    const [frames, com, support, inside, fallen] = pose;
    frames.forEach((m, i) => {
      const group = this.links[i];
      group.matrix.copy(matrix(m));
      group.matrixWorldNeedsUpdate = true;
    });
    const colour = fallen ? 0xdc2626 : inside ? 0x16a34a : 0xea580c;
    this.com.material.color.setHex(colour);
    this.plumb.material.color.setHex(colour);
    this.com.position.set(com[0], com[1], 2 * GROUND_LIFT);
    setPoints(this.plumb.geometry, [com, [com[0], com[1], GROUND_LIFT]]);
    const ring = support.map((p) => [p[0], p[1], GROUND_LIFT]);
    setPoints(this.outline.geometry, ring);
    const fan = [];
    for (let i = 1; i + 1 < ring.length; i++) fan.push(ring[0], ring[i], ring[i + 1]);
    setPoints(this.area.geometry, fan);
  }
}
