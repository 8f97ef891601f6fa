// three.js scene: the evolving surface with optional wireframe and per-vertex colours.
// It draws into an OffscreenCanvas inside the render worker, so even a CPU rasteriser drawing a
// large mesh never blocks the page; camera motion arrives as small messages from the UI thread.
import * as THREE from 'three';
import type { FieldIso, FieldSlice } from './protocol';

/** Copies into the existing attribute when sizes match (reusing its GPU buffer), else replaces it. */
function setOrCopy(g: THREE.BufferGeometry, name: string, data: Float32Array): void {
  const a = g.getAttribute(name) as THREE.BufferAttribute | undefined;
  if (a && a.array.length === data.length) {
    (a.array as Float32Array).set(data);
    a.needsUpdate = true;
  } else {
    g.setAttribute(name, new THREE.BufferAttribute(data, 3));
  }
}

/** True when WebGL runs on a CPU rasteriser (SwiftShader, llvmpipe, …). */
export function isSoftwareRenderer(gl: WebGL2RenderingContext | WebGLRenderingContext | null): boolean {
  if (!gl) return false;
  const ext = gl.getExtension('WEBGL_debug_renderer_info');
  const name = ext ? String(gl.getParameter(ext.UNMASKED_RENDERER_WEBGL)) : '';
  return /swiftshader|llvmpipe|software|softpipe/i.test(name);
}

/** At most this many target points are drawn. */
const MAX_TARGET_POINTS = 50_000;

/** Every `k`-th point of `positions` (x, y, z triples). */
function everyKth(positions: Float32Array, k: number): Float32Array {
  const n = Math.ceil(positions.length / 3 / k);
  const out = new Float32Array(3 * n);
  for (let i = 0; i < n; i++) out.set(positions.subarray(3 * i * k, 3 * i * k + 3), 3 * i);
  return out;
}

/** An orbiting camera: yaw/pitch about a target at a distance (no DOM needed). */
export class Orbit {
  target = new THREE.Vector3();
  distance = 3;
  yaw = 0.35;
  pitch = 0.4;

  apply(camera: THREE.PerspectiveCamera): void {
    const c = Math.cos(this.pitch);
    const dir = new THREE.Vector3(c * Math.sin(this.yaw), Math.sin(this.pitch), c * Math.cos(this.yaw));
    camera.position.copy(this.target).addScaledVector(dir, this.distance);
    camera.near = this.distance / 100;
    camera.far = this.distance * 10;
    camera.lookAt(this.target);
    camera.updateProjectionMatrix();
  }

  rotate(dx: number, dy: number): void {
    this.yaw -= dx * 0.008;
    this.pitch = Math.max(-1.5, Math.min(1.5, this.pitch + dy * 0.008));
  }

  zoom(factor: number): void {
    this.distance = Math.max(1e-6, this.distance * factor);
  }
}

export class Viewer {
  private readonly renderer: THREE.WebGLRenderer;
  private readonly scene = new THREE.Scene();
  private readonly camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
  private readonly orbit = new Orbit();
  private readonly geometry = new THREE.BufferGeometry();
  private readonly wire: THREE.Mesh;
  private readonly surfaceMaterial = new THREE.MeshStandardMaterial({
    color: 0xb8c4d6, vertexColors: true, roughness: 0.55, metalness: 0.05,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
  private fitted = false;
  /** A view to apply after the next fit (from a share link). */
  pendingView: { yaw: number; pitch: number; zoom: number } | null = null;
  private fitDistance = 3;
  private target: THREE.Object3D | null = null;
  private targetVisible = true;
  private width = 1;
  private height = 1;
  /** The distance-field view: a textured slice quad or a translucent isosurface. */
  private field: THREE.Mesh | null = null;

  constructor(canvas: OffscreenCanvas | HTMLCanvasElement, pixelRatio: number) {
    const probe = canvas.getContext('webgl2', { preserveDrawingBuffer: true }) as WebGL2RenderingContext | null;
    // Multisampling costs a CPU rasteriser dearly; keep it for real GPUs only.
    const software = isSoftwareRenderer(probe);
    this.renderer = new THREE.WebGLRenderer({ canvas, context: probe ?? undefined, antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(pixelRatio * (software ? 0.5 : 1));
    this.scene.background = new THREE.Color(0x15171c);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x30343c, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(2, 3, 4);
    this.camera.add(sun);
    this.scene.add(this.camera);
    // The wireframe shares the surface geometry; three.js rebuilds its edge list only when the
    // index changes.
    this.wire = new THREE.Mesh(this.geometry, new THREE.MeshBasicMaterial({ color: 0x0b0d12, wireframe: true, transparent: true, opacity: 0.3 }));
    this.scene.add(new THREE.Mesh(this.geometry, this.surfaceMaterial), this.wire);
  }

  resize(width: number, height: number): void {
    this.width = Math.max(1, width);
    this.height = Math.max(1, height);
    this.renderer.setSize(this.width, this.height, false);
    this.camera.aspect = this.width / this.height;
    this.orbit.apply(this.camera);
  }

  /** Replaces the surface buffers (indices only when connectivity changed). */
  update(positions: Float32Array, normals: Float32Array, indices: Uint32Array | undefined, colors: Float32Array | null): void {
    const g = this.geometry;
    if (indices) {
      // New connectivity: drop the old GPU buffers before uploading new ones.
      g.dispose();
      for (const name of Object.keys(g.attributes)) g.deleteAttribute(name);
      g.setIndex(new THREE.BufferAttribute(indices, 1));
    }
    setOrCopy(g, 'position', positions);
    setOrCopy(g, 'normal', normals);
    if (colors) setOrCopy(g, 'color', colors);
    else if (g.getAttribute('color')) g.deleteAttribute('color');
    if (this.surfaceMaterial.vertexColors !== !!colors) {
      this.surfaceMaterial.vertexColors = !!colors;
      this.surfaceMaterial.needsUpdate = true;
    }
    g.computeBoundingSphere();
    if (!this.fitted) {
      const keep = this.getView();
      this.fit();
      if (this.pendingView) {
        this.setView(this.pendingView.yaw, this.pendingView.pitch, this.pendingView.zoom);
        this.pendingView = null;
      } else this.setView(keep.yaw, keep.pitch, 1);
    }
  }

  /** Frames the whole surface. */
  fit(): void {
    const s = this.geometry.boundingSphere;
    if (!s) return;
    this.orbit.target.copy(s.center);
    this.fitDistance = (s.radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2))) * 1.1;
    this.orbit.distance = this.fitDistance;
    this.orbit.apply(this.camera);
    this.fitted = true;
  }

  /** Shows the target: points, or a faded mesh when it has triangles. */
  setTarget(positions: Float32Array, indices: Uint32Array | null): void {
    if (this.target) {
      this.scene.remove(this.target);
      const t = this.target as THREE.Mesh | THREE.Points;
      t.geometry.dispose();
      (t.material as THREE.Material).dispose();
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.computeBoundingSphere();
    const r = g.boundingSphere?.radius ?? 1;
    if (indices && indices.length) {
      g.setIndex(new THREE.BufferAttribute(indices, 1));
      g.computeVertexNormals();
      this.target = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: 0xffc266, transparent: true, opacity: 0.22, depthWrite: false, side: THREE.DoubleSide }));
    } else {
      // A dense cloud is drawn thinned (every k-th point): what is drawn, not what is computed.
      const k = Math.ceil(positions.length / 3 / MAX_TARGET_POINTS);
      if (k > 1) g.setAttribute('position', new THREE.BufferAttribute(everyKth(positions, k), 3));
      this.target = new THREE.Points(g, new THREE.PointsMaterial({ color: 0xffc266, size: Math.max(1e-6, r * 0.0035), sizeAttenuation: true }));
    }
    this.target.visible = this.targetVisible;
    this.scene.add(this.target);
  }

  /** Shows a field slice (textured quad), an isosurface (translucent mesh), or nothing. */
  setField(slice?: FieldSlice, iso?: FieldIso): void {
    if (this.field) {
      this.scene.remove(this.field);
      this.field.geometry.dispose();
      const m = this.field.material as THREE.MeshBasicMaterial;
      m.map?.dispose();
      m.dispose();
      this.field = null;
    }
    if (slice) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(slice.corners, 3));
      g.setAttribute('uv', new THREE.BufferAttribute(new Float32Array([0, 0, 1, 0, 1, 1, 0, 1]), 2));
      g.setIndex([0, 1, 2, 0, 2, 3]);
      const tex = new THREE.DataTexture(slice.rgba, slice.width, slice.height, THREE.RGBAFormat);
      tex.colorSpace = THREE.SRGBColorSpace;
      tex.magFilter = THREE.LinearFilter;
      tex.minFilter = THREE.LinearFilter;
      tex.needsUpdate = true;
      this.field = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ map: tex, side: THREE.DoubleSide, transparent: true, opacity: 0.85, depthWrite: false }));
    } else if (iso && iso.indices.length) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(iso.positions, 3));
      g.setIndex(new THREE.BufferAttribute(iso.indices, 1));
      g.computeVertexNormals();
      this.field = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: 0x5fd3a0, roughness: 0.6, transparent: true, opacity: 0.4, depthWrite: false, side: THREE.DoubleSide }));
    }
    if (this.field) {
      this.field.renderOrder = 2;
      this.scene.add(this.field);
    }
  }

  showTarget(on: boolean): void {
    this.targetVisible = on;
    if (this.target) this.target.visible = on;
  }

  /** Flat (per-face) or smooth (per-vertex normal) shading. */
  setSmooth(on: boolean): void {
    if (this.surfaceMaterial.flatShading === !on) return;
    this.surfaceMaterial.flatShading = !on;
    this.surfaceMaterial.needsUpdate = true;
  }

  /** Orbit angles and zoom relative to the fitted distance (what a share link carries). */
  getView(): { yaw: number; pitch: number; zoom: number } {
    return { yaw: this.orbit.yaw, pitch: this.orbit.pitch, zoom: this.orbit.distance / this.fitDistance };
  }

  setView(yaw: number, pitch: number, zoom: number): void {
    this.orbit.yaw = yaw;
    this.orbit.pitch = Math.max(-1.5, Math.min(1.5, pitch));
    this.orbit.distance = this.fitDistance * Math.max(1e-3, zoom);
    this.orbit.apply(this.camera);
  }

  /** Frames the current surface now, keeping the orbit angles. */
  fitKeepingAngles(): void {
    const { yaw, pitch } = this.getView();
    this.fit();
    this.setView(yaw, pitch, 1);
  }

  /** Forgets the framing so the next update fits the view again. */
  refit(): void {
    this.fitted = false;
  }

  rotate(dx: number, dy: number): void {
    this.orbit.rotate(dx, dy);
    this.orbit.apply(this.camera);
  }

  zoom(factor: number): void {
    this.orbit.zoom(factor);
    this.orbit.apply(this.camera);
  }

  setWireframe(on: boolean): void {
    this.wire.visible = on;
  }

  render(): void {
    this.renderer.render(this.scene, this.camera);
  }

  /** Fraction of drawn pixels that differ from the background (a test and sanity probe). */
  meshPixelFraction(): number {
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 0x15) + Math.abs(px[i + 1] - 0x17) + Math.abs(px[i + 2] - 0x1c) > 24) n++;
    }
    return n / (w * h);
  }
}
