// The example scene (docs/three.md): two rows of spheres from rough to polished, dielectric on top
// and metal below, under a sky and ground (HemisphereLight), an ambient light and a sun
// (DirectionalLight). `THREE` is passed in, so that the page (import map) and Node
// (js/ganzfeld-three/bin/scene-file.js, which writes examples/three/scene.json) build the same scene.

/// Roughness of each column, rough to polished: those whose tables `--max-error 2e-2` bakes in
/// seconds to a minute today (docs/three.md, "Tables").
export const kRoughness = [0.9, 0.7, 0.5, 0.4];

/// {scene, camera, materials}: camera at (0, 0, 12) looking at the origin, 30° vertical field of
/// view, for an image of aspect `aspect`.
export function buildExampleScene(THREE, aspect = 16 / 9) {
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(30, aspect, 0.1, 100);
  camera.position.set(0, 0, 12);
  camera.lookAt(0, 0, 0);

  const rows = [
    {kind: 'dielectric', color: new THREE.Color(0.7, 0.12, 0.08), metalness: 0, y: 1.15},
    {kind: 'metal', color: new THREE.Color(1.0, 0.71, 0.29), metalness: 1, y: -1.15},  // gold's f0 (linear)
  ];
  const geometry = new THREE.SphereGeometry(1, 256, 128);
  const materials = [];
  for (const row of rows)
    kRoughness.forEach((roughness, column) => {
      const material = new THREE.MeshStandardMaterial({color: row.color, metalness: row.metalness, roughness});
      material.name = `${row.kind}_r${String(roughness).replace('.', '_')}`;
      const sphere = new THREE.Mesh(geometry, material);
      sphere.name = material.name;
      sphere.position.set((column - (kRoughness.length - 1) / 2) * 2.3, row.y, 0);
      scene.add(sphere);
      materials.push(material);
    });

  const sky = new THREE.HemisphereLight(new THREE.Color(0.55, 0.7, 1.0), new THREE.Color(0.25, 0.2, 0.12), 2.0);
  sky.position.set(0.2, 1, 0.3);
  sky.name = 'sky';
  scene.add(sky);
  const ambient = new THREE.AmbientLight(new THREE.Color(1, 1, 1), 0.3);
  ambient.name = 'ambient';
  scene.add(ambient);
  const sun = new THREE.DirectionalLight(new THREE.Color(1, 0.95, 0.85), 2.0);
  sun.position.set(-3, 4, 5);
  sun.name = 'sun';
  scene.add(sun);
  return {scene, camera, materials};
}
