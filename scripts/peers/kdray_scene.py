"""Reads a kdray scene file (docs/scene-format.md) into plain numpy arrays,
for the peer renderers in this folder (Embree, Mitsuba 3). Not part of the
crate; it trusts the file to be valid (run `kdray render` on it first) and
reads only what the peers need: camera, render size and samples, lights,
materials, spheres, triangles and OBJ meshes (v and f; MTL Ka/Kd/Ks/Ns).
For the path tracer (`integrator = "path"`) it also reads the physical
material keys (transmission, ior, base_color, metallic, roughness,
emission) and the `[environment]` table; `diffuse` then holds the albedo,
the base colour where a material gives `base_color`, as kdray does.
"""

import json
import math
import os
import tomllib
from dataclasses import dataclass, field

import numpy as np

RENDER_DEFAULTS = {
    "width": 800,
    "height": 600,
    "min_intensity": 0.05,
    "max_depth": 10,
    "background": [0.0, 0.0, 0.0],
    "shadow_mode": "ambient",
    "samples": 1,
    "integrator": "whitted",
    "seed": 0,
}


@dataclass
class Material:
    ambient: tuple = (0.0, 0.0, 0.0)
    diffuse: tuple = (0.0, 0.0, 0.0)
    specular: tuple = (0.0, 0.0, 0.0)
    shininess: float = 0.0
    reflection: float = 0.0
    # The path tracer's keys (docs/scene-format.md): `model` is "lambertian"
    # (albedo `diffuse`) or "metal_rough" (base colour `diffuse`, metallic,
    # roughness); emission is radiance (W / (sr m^2) per channel).
    transmission: float = 0.0
    ior: float = 1.5
    model: str = "lambertian"
    metallic: float = 0.0
    roughness: float = 0.5
    emission: tuple = (0.0, 0.0, 0.0)


@dataclass
class Scene:
    path: str
    camera: dict
    render: dict
    lights: list
    materials: dict  # name -> Material
    # Spheres: centres (S, 3), radii (S,), material names.
    sphere_centers: np.ndarray
    sphere_radii: np.ndarray
    sphere_materials: list
    # Triangles, scene [[triangles]] first, then each mesh in file order:
    # vertices (T, 3, 3) in world space (float64), material names.
    triangles: np.ndarray
    triangle_materials: list = field(default_factory=list)
    # `[environment]` as written ({} when absent): `color` is a uniform sky,
    # `image` a sky image (a path relative to the scene's folder, as
    # written: `folder` resolves it).
    environment: dict = field(default_factory=dict)
    # The scene file's folder.
    folder: str = ""


def load(path):
    with open(path, "rb") as f:
        data = f.read()
    if path.lower().endswith(".json"):
        doc = json.loads(data)
    else:
        doc = tomllib.loads(data.decode("utf-8"))
    folder = os.path.dirname(os.path.abspath(path))

    camera = dict(doc["camera"])
    camera.setdefault("up", [0.0, 1.0, 0.0])
    camera.setdefault("vfov", 60.0)
    render = dict(RENDER_DEFAULTS)
    render.update(doc.get("render", {}))
    lights = []
    # Path scenes may have no point lights (emitters and the sky light them).
    for light in doc.get("lights", []):
        lights.append(
            {
                "kind": light.get("kind", "point"),
                # None for a directional light (which has a direction only).
                "position": light.get("position"),
                "direction": light.get("direction"),
                "reference_distance": light.get("reference_distance"),
                "ambient": light.get("ambient", [1.0, 1.0, 1.0]),
                "diffuse": light.get("diffuse", [1.0, 1.0, 1.0]),
                "specular": light.get("specular", [1.0, 1.0, 1.0]),
            }
        )
    materials = {name: _material(m) for name, m in doc.get("materials", {}).items()}

    spheres = doc.get("spheres", [])
    centers = np.array([s["center"] for s in spheres], dtype=np.float64).reshape(-1, 3)
    radii = np.array([s["radius"] for s in spheres], dtype=np.float64)
    sphere_materials = [s["material"] for s in spheres]

    tris = [np.array(t["vertices"], dtype=np.float64) for t in doc.get("triangles", [])]
    tri_materials = [t["material"] for t in doc.get("triangles", [])]
    for mesh in doc.get("meshes", []):
        obj_path = mesh["path"]
        if not os.path.isabs(obj_path):
            obj_path = os.path.join(folder, obj_path)
        faces, face_materials, mtl = _read_obj(obj_path, mesh.get("material") is None)
        for name, m in mtl.items():
            materials[name] = m
        faces = _transform(
            faces,
            mesh.get("scale", 1.0),
            mesh.get("rotate", [0.0, 0.0, 0.0]),
            mesh.get("translate", [0.0, 0.0, 0.0]),
        )
        # Faces of zero area (degenerate, or collapsed by the transform) are
        # skipped, as kdray does.
        area2 = np.linalg.norm(
            np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0]), axis=1
        )
        keep = area2 > 0.0
        tris.extend(faces[keep])
        if mesh.get("material") is not None:
            tri_materials.extend([mesh["material"]] * int(keep.sum()))
        else:
            tri_materials.extend(m for m, k in zip(face_materials, keep) if k)
    triangles = np.array(tris, dtype=np.float64).reshape(-1, 3, 3)
    return Scene(
        path=path,
        camera=camera,
        render=render,
        lights=lights,
        materials=materials,
        sphere_centers=centers,
        sphere_radii=radii,
        sphere_materials=sphere_materials,
        triangles=triangles,
        triangle_materials=tri_materials,
        environment=dict(doc.get("environment", {})),
        folder=folder,
    )


def _material(m):
    # Exactly one of diffuse (Lambertian) and base_color (metal/rough).
    metal_rough = "base_color" in m
    return Material(
        ambient=tuple(m.get("ambient", [0.0, 0.0, 0.0])),
        diffuse=tuple(m["base_color"] if metal_rough else m["diffuse"]),
        specular=tuple(m.get("specular", [0.0, 0.0, 0.0])),
        shininess=float(m.get("shininess", 0.0)),
        reflection=float(m.get("reflection", 0.0)),
        transmission=float(m.get("transmission", 0.0)),
        ior=float(m.get("ior", 1.5)),
        model="metal_rough" if metal_rough else "lambertian",
        metallic=float(m.get("metallic", 0.0)),
        roughness=float(m.get("roughness", 0.5)),
        emission=tuple(m.get("emission", [0.0, 0.0, 0.0])),
    )


def _read_obj(path, want_materials):
    """Faces of an OBJ file, fan-triangulated: (F, 3, 3) float64, each face's
    material name (`file.obj:name`, as kdray names MTL materials), and those
    materials."""
    base = os.path.basename(path)
    folder = os.path.dirname(path)
    vertices = []
    faces = []
    face_materials = []
    materials = {}
    current = None
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            head, _, rest = line.partition(" ")
            if head == "v":
                vertices.append([float(x) for x in rest.split()[:3]])
            elif head == "f":
                idx = []
                for token in rest.split():
                    i = int(token.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(vertices) + i)
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
                    face_materials.append(current)
            elif head == "usemtl" and want_materials:
                current = f"{base}:{rest.strip()}"
            elif head == "mtllib" and want_materials:
                for name in rest.split():
                    for mname, m in _read_mtl(os.path.join(folder, name)).items():
                        materials.setdefault(f"{base}:{mname}", m)
    v = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    return v[np.array(faces, dtype=np.int64).reshape(-1, 3)], face_materials, materials


def _read_mtl(path):
    out = {}
    current = None
    keys = {"Ka": "ambient", "Kd": "diffuse", "Ks": "specular"}
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            head, _, rest = line.partition(" ")
            if head == "newmtl":
                current = Material()
                out.setdefault(rest.strip(), current)
            elif current is not None and head in keys:
                values = [float(x) for x in rest.split()[:3]]
                if len(values) == 1:
                    values *= 3
                setattr(current, keys[head], tuple(values))
            elif current is not None and head == "Ns":
                current.shininess = float(rest.split()[0])
    return out


def _transform(faces, scale, rotate, translate):
    """v' = Rz * Ry * Rx * (scale * v) + translate, angles in degrees."""
    s = np.array([scale] * 3 if isinstance(scale, (int, float)) else scale, dtype=np.float64)
    ax, ay, az = (math.radians(a) for a in rotate)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    m = rz @ ry @ rx
    return (faces * s) @ m.T + np.array(translate, dtype=np.float64)


def camera_basis(camera):
    """forward, right, true_up (unit vectors) and tan(vfov / 2), as in
    docs/scene-format.md (Camera)."""
    pos = np.array(camera["position"], dtype=np.float64)
    forward = np.array(camera["look_at"], dtype=np.float64) - pos
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera["up"], dtype=np.float64))
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    return forward, right, true_up, math.tan(math.radians(camera["vfov"]) / 2.0)



def mitsuba_sensor(mi, camera, width, height, spp):
    """Mitsuba 3's sensor (a scene dict entry) for kdray's `camera`: the
    same view and vertical field of view, a `width` x `height` RGB film
    with a box filter and `spp` independent samples per pixel. `mi` is the
    mitsuba module."""
    return {
        "type": "perspective",
        "fov": float(camera["vfov"]),
        "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(
            origin=camera["position"], target=camera["look_at"], up=camera["up"]
        ),
        "film": {
            "type": "hdrfilm",
            "width": width,
            "height": height,
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
        },
        "sampler": {"type": "independent", "sample_count": spp},
    }

def primary_rays(scene, width=None, height=None):
    """kdray's primary rays (shaders/trace.wgsl `camera_ray`): one per pixel
    centre, or the k x k sub-cell centres when samples = k * k; row-major,
    top row first. Returns origins and unit directions, (N, 3) float32."""
    w = width or scene.render["width"]
    h = height or scene.render["height"]
    k = math.isqrt(scene.render["samples"])
    forward, right, true_up, t = camera_basis(scene.camera)
    # Sub-cell centres along each axis, in pixel units.
    cells = (np.arange(k) + 0.5) / k
    xs = (np.arange(w)[:, None] + cells[None, :]).reshape(-1)
    ys = (np.arange(h)[:, None] + cells[None, :]).reshape(-1)
    # kdray computes in f32 on the GPU; directions differ from these by
    # rounding only.
    u = (xs / w).astype(np.float32)
    v = (ys / h).astype(np.float32)
    f32 = np.float32
    a = (2 * u - 1) * f32(t * w / h)
    b = (1 - 2 * v) * f32(t)
    dirs = (
        forward.astype(f32)[None, None, :]
        + a[None, :, None] * right.astype(f32)[None, None, :]
        + b[:, None, None] * true_up.astype(f32)[None, None, :]
    ).reshape(-1, 3)
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    origins = np.broadcast_to(np.array(scene.camera["position"], dtype=f32), dirs.shape)
    return np.ascontiguousarray(origins), np.ascontiguousarray(dirs, dtype=f32)
