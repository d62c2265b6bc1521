// The page the browser tests drive (run.mjs): Babylon.js renders what a
// job asks for into a float render target and hands back its linear
// texels, rows top-down, as base64 of little-endian f32 RGBA.

let B = null;
let engine = null;

async function init() {
  if (B) return;
  B = await import("/node_modules/@babylonjs/core/index.js");
  const canvas = document.getElementById("c");
  engine = new B.Engine(canvas, false, { preserveDrawingBuffer: true, antialias: false });
}

function newScene() {
  const scene = new B.Scene(engine);
  scene.clearColor = new B.Color4(0, 0, 0, 1);
  // Linear output: the PBR shader's final colour as it is, no gamma and
  // no clamp (IMAGEPROCESSINGPOSTPROCESS with SKIPFINALCOLORCLAMP; no
  // post-process is attached).
  scene.imageProcessingConfiguration.applyByPostProcess = true;
  scene.imageProcessingConfiguration.skipFinalColorClamp = true;
  return scene;
}

function loadEnv(scene, url) {
  return new Promise((resolve, reject) => {
    const t = new B.CubeTexture(url, scene, undefined, false, undefined,
      () => resolve(t), (m, e) => reject(new Error(`${url}: ${m} ${e ?? ""}`)));
  });
}

function loadHdr(scene, url, size) {
  return new Promise((resolve, reject) => {
    // size, noMipmap, generateHarmonics, gammaSpace, prefilterOnLoad
    const t = new B.HDRCubeTexture(url, scene, size, false, true, false, true,
      () => resolve(t), (m, e) => reject(new Error(`${url}: ${m} ${e ?? ""}`)));
  });
}

// A glTF file's image-based light (EXT_lights_image_based), through
// Babylon.js's glTF loader, which makes it the scene's environment.
async function loadGltf(scene, url) {
  await import("/node_modules/@babylonjs/loaders/glTF/index.js");
  await B.SceneLoader.AppendAsync("", url, scene);
  for (let i = 0; i < 1200; i++) {
    const t = scene.environmentTexture;
    if (t && t.isReady()) return t;
    await new Promise((r) => setTimeout(r, 50));
  }
  throw new Error(`${url}: no environment after 60 s`);
}

// The environment of a job: a .env, a Radiance file (kind "hdr"), or a
// glTF light (kind "gltf").
function loadKind(scene, job) {
  if (job.kind === "hdr") return loadHdr(scene, job.env, job.size);
  if (job.kind === "gltf") return loadGltf(scene, job.env);
  return loadEnv(scene, job.env);
}

function b64(f32) {
  const u8 = new Uint8Array(f32.buffer, f32.byteOffset, f32.byteLength);
  let s = "";
  for (let i = 0; i < u8.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, u8.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

// Renders `meshes` seen by `camera` into a w×h RGBA32F target; the texels,
// rows top-down.
async function renderFloat(scene, camera, meshes, w, h) {
  const rt = new B.RenderTargetTexture("rt", { width: w, height: h }, scene, false, true,
    B.Constants.TEXTURETYPE_FLOAT, false, B.Constants.TEXTURE_NEAREST_SAMPLINGMODE);
  rt.activeCamera = camera;
  rt.renderList = meshes;
  rt.clearColor = new B.Color4(0, 0, 0, 0);
  scene.customRenderTargets.push(rt);
  await scene.whenReadyAsync();
  for (const m of meshes) {
    if (m.material) await new Promise((r) => { const go = () => m.material.isReady(m) ? r() : setTimeout(go, 20); go(); });
  }
  scene.render();
  const px = new Float32Array(await rt.readPixels());
  rt.dispose();
  scene.customRenderTargets.length = 0;
  const out = new Float32Array(px.length);
  const row = w * 4;
  for (let y = 0; y < h; y++) out.set(px.subarray((h - 1 - y) * row, (h - y) * row), y * row);
  return out;
}

// The skybox (createDefaultSkybox: a PBR box that reads the cube at level
// 0) of a .env file, or of a Radiance file as HDRCubeTexture reads it
// (kind "hdr"), seen from the origin with a vertical field of view `fov` (radians),
// looking at `dir` with `up`, one image per view.
window.skybox = async function (job) {
  await init();
  const scene = newScene();
  const tex = await loadKind(scene, job);
  const sky = scene.createDefaultSkybox(tex, true, 1000, 0, false);
  const cam = new B.FreeCamera("cam", B.Vector3.Zero(), scene);
  cam.fov = job.fov; cam.minZ = 0.1; cam.maxZ = 10000;
  const images = [];
  for (const v of job.views) {
    cam.upVector = new B.Vector3(...v.up);
    cam.setTarget(new B.Vector3(...v.dir));
    images.push(b64(await renderFloat(scene, cam, [sky], job.width, job.height)));
  }
  scene.dispose();
  return { images };
};

// Spheres of radius 1 at the origin, seen by an orthographic camera far
// on −z looking along +z (up +y) whose view is [−1, 1]²: one image per
// roughness. `source` is a .env file ("env") or a Radiance file that
// Babylon.js prefilters itself ("hdr", HDRCubeTexture with prefilterOnLoad
// at `size`). The material is the PBR metallic-roughness one with the
// split sum alone: Lambert's diffuse (not the default energy-preserving
// Oren–Nayar), no radiance-irradiance mix, no multiscatter energy factor,
// the irradiance per pixel.
window.spheres = async function (job) {
  await init();
  const scene = newScene();
  const tex = await loadKind(scene, job);
  scene.environmentTexture = tex;
  // Far away: Babylon.js's shaders take the view vector from the eye's
  // position even for an orthographic camera; at 10⁴ it is +z within 10⁻⁴.
  const cam = new B.FreeCamera("cam", new B.Vector3(0, 0, -1e4), scene);
  cam.mode = B.Camera.ORTHOGRAPHIC_CAMERA;
  cam.orthoLeft = -1; cam.orthoRight = 1; cam.orthoTop = 1; cam.orthoBottom = -1;
  cam.minZ = 1e4 - 2; cam.maxZ = 1e4 + 2;
  cam.setTarget(B.Vector3.Zero());
  const sphere = B.MeshBuilder.CreateSphere("s", { diameter: 2, segments: job.segments ?? 128 }, scene);
  const images = [];
  for (const r of job.roughness) {
    const m = new B.PBRMaterial("m", scene);
    m.albedoColor = new B.Color3(...job.base);
    m.metallic = job.metallic;
    m.roughness = r;
    m.brdf.mixIblRadianceWithIrradiance = false;
    m.brdf.useEnergyConservation = false;
    m.brdf.baseDiffuseModel = B.Constants.MATERIAL_DIFFUSE_MODEL_LAMBERT;
    m.forceIrradianceInFragment = true;
    sphere.material = m;
    images.push(b64(await renderFloat(scene, cam, [sphere], job.width, job.height)));
    m.dispose();
  }
  const info = { lodGenerationScale: tex.lodGenerationScale, width: tex.getSize().width };
  scene.dispose();
  return { images, info };
};

// A picture for people: the skybox and two rows of spheres, metal above
// and plastic below, roughness 0 to 1 from left to right, rendered to the
// canvas with Babylon.js's default output (gamma 2.2); a PNG.
window.gallery = async function (job) {
  await init();
  const canvas = document.getElementById("c");
  canvas.width = job.width; canvas.height = job.height;
  engine.resize();
  const scene = new B.Scene(engine);
  const tex = await loadKind(scene, job);
  scene.environmentTexture = tex;
  scene.imageProcessingConfiguration.exposure = job.exposure ?? 1;
  scene.createDefaultSkybox(tex, true, 1000, 0, false);
  const cam = new B.FreeCamera("cam", new B.Vector3(...job.eye), scene);
  cam.fov = job.fov; cam.minZ = 0.1; cam.maxZ = 10000;
  cam.setTarget(new B.Vector3(...job.target));
  const n = job.roughness.length;
  job.roughness.forEach((r, i) => {
    for (const [row, metallic, base] of [[1, 1, [1, 1, 1]], [-1, 0, [0.5, 0.5, 0.5]]]) {
      const s = B.MeshBuilder.CreateSphere(`s${i}${row}`, { diameter: 1.8, segments: 64 }, scene);
      s.position = new B.Vector3((i - (n - 1) / 2) * 2.1, row * 1.05, 0);
      const m = new B.PBRMaterial(`m${i}${row}`, scene);
      m.albedoColor = new B.Color3(...base);
      m.metallic = metallic;
      m.roughness = r;
      s.material = m;
    }
  });
  await scene.whenReadyAsync();
  scene.render();
  scene.render();
  const png = canvas.toDataURL("image/png").split(",")[1];
  scene.dispose();
  return { images: [], png };
};

window.pageReady = true;
