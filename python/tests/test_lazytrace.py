"""Tests of the Python module: the C API's hits through Python, the trimesh-shaped helpers against
a brute-force numpy reference, statistics, persistence, and bad input.

LAZYTRACE_LIBRARY names the shared library and LAZYTRACE_TOOL the command-line tool (the C
API's answers to compare with); tests/CMakeLists.txt sets both. LAZYTRACE_TEST_OPENCL=1 adds
the OpenCL backend to the comparison with the C API."""
import os
import subprocess

import numpy as np
import pytest

import lazytrace

NATIVE = lazytrace.Context("native", quiet=True)


def random_rays(scene, n, seed):
    """Rays between random points of the scene's box, grown by a tenth on each side."""
    lo, hi = (b.astype(np.float64) for b in scene.bounds)
    pad = 0.1 * (hi - lo)
    rng = np.random.default_rng(seed)
    a = rng.uniform(lo - pad, hi + pad, (n, 3))
    b = rng.uniform(lo - pad, hi + pad, (n, 3))
    return a.astype(np.float32), (b - a).astype(np.float32)


# ---- The C API's hits, bit for bit ----

def c_api_hits(tmp_path, spec, rays, kind, build, device, any_hit=False):
    """What the command-line tool (the C API) answers for these rays."""
    tool = os.environ.get("LAZYTRACE_TOOL")
    if not tool:
        pytest.skip("LAZYTRACE_TOOL is not set")
    ray_file, hit_file = tmp_path / "in.rays", tmp_path / "out.hits"
    rays.tofile(ray_file)
    command = [tool, "trace", spec, "--rays", str(ray_file), "--hits", str(hit_file), "--structure", kind,
               "--build", build, "--device", device] + (["--any"] if any_hit else [])
    subprocess.run(command, check=True, capture_output=True)
    return np.fromfile(hit_file, lazytrace.HIT_DTYPE)


_contexts = {"native": NATIVE}


def contexts():
    """The backends to compare on, each with one context for the whole run (kernels are
    compiled once per context)."""
    wanted = os.environ.get("LAZYTRACE_TEST_OPENCL") == "1" and not os.environ.get("LT_TEST_NATIVE_ONLY")
    if wanted and "opencl" not in _contexts:
        try:
            _contexts["opencl"] = lazytrace.Context("opencl", quiet=True)
        except lazytrace.LazytraceError as error:  # no OpenCL device on this machine
            assert error.name == "LT_ERROR_NO_DEVICE", error
            _contexts["opencl"] = None
    return [(device, context) for device, context in _contexts.items() if context is not None]


@pytest.mark.parametrize("spec", ["sphere:2", "cornell"])
@pytest.mark.parametrize("kind,build", lazytrace.variants())
def test_hits_equal_the_c_api(tmp_path, spec, kind, build):
    scene = lazytrace.Scene.load(spec)
    origins, directions = random_rays(scene, 300, seed=len(spec))
    rays = np.zeros(len(origins), lazytrace.RAY_DTYPE)
    rays["org"], rays["dir"], rays["tmax"] = origins, directions, np.inf
    for device, context in contexts():
        structure = lazytrace.Structure(scene, kind=kind, build=build, context=context)
        t, prim, _, _ = structure.intersect(origins, directions)
        expected = c_api_hits(tmp_path, spec, rays, kind, build, device)
        assert np.array_equal(prim, expected["prim"]), (device, kind, build)
        assert np.array_equal(t.view(np.uint32), expected["t"].view(np.uint32)), (device, kind, build)
        blocked = structure.occluded(origins, directions)
        expected = c_api_hits(tmp_path, spec, rays, kind, build, device, any_hit=True)
        assert np.array_equal(blocked, expected["prim"] >= 0), (device, kind, build)


def test_float64_and_strided_input_give_the_float32_answers():
    scene = lazytrace.Scene.load("sphere:2")
    structure = lazytrace.Structure(scene, context=NATIVE)
    origins, directions = random_rays(scene, 200, seed=7)
    reference = structure.intersect(origins, directions)
    # Every other row of a float64 array twice as long, and Fortran-ordered directions.
    wide = np.zeros((400, 3))
    wide[::2] = origins
    for o, d in [(wide[::2], directions), (origins, np.asfortranarray(directions.astype(np.float64)))]:
        again = structure.intersect(o, d)
        for got, want in zip(again, reference):
            assert np.array_equal(got, want)


def test_records_equal_the_reference_trace():
    scene = lazytrace.Scene.load("cornell")
    structure = lazytrace.Structure(scene, kind="kdtree", build="requested", context=NATIVE)
    origins, directions = random_rays(scene, 100, seed=3)
    rays = np.zeros(len(origins), lazytrace.RAY_DTYPE)
    rays["org"], rays["dir"], rays["tmax"] = origins, directions, np.inf
    hits = structure.trace_records(rays)
    by_columns = structure.trace_records(rays.view(np.float32).reshape(-1, 8))
    assert hits.tobytes() == by_columns.tobytes()
    assert np.array_equal(hits["prim"], structure.intersect(origins, directions).prim)


# ---- trimesh-shaped helpers against brute force ----

def cube():
    """A closed unit cube with shared vertices, 12 triangles."""
    vertices = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return vertices, np.array(faces)


def sphere_arrays():
    """sphere:1 as vertices and faces (three vertices per face), 80 triangles."""
    triangles = lazytrace.Scene.load("sphere:1").triangles.astype(np.float64)
    return triangles.reshape(-1, 3), np.arange(len(triangles) * 3).reshape(-1, 3)


def brute_force(vertices, faces, origins, directions):
    """Every (ray, triangle, t, margin) crossing with t > 0, in float64 (Moller-Trumbore);
    margin is the smallest barycentric, so that hits near an edge can be left out."""
    v0, v1, v2 = (vertices[faces[:, k]] for k in range(3))
    e1, e2 = v1 - v0, v2 - v0
    p = np.cross(directions[:, None, :], e2[None])
    det = np.einsum("rfk,fk->rf", p, e1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origins[:, None, :] - v0[None]
        u = np.einsum("rfk,rfk->rf", s, p) * inv
        q = np.cross(s, e1[None])
        v = np.einsum("rfk,rk->rf", q, directions) * inv
        t = np.einsum("rfk,fk->rf", q, e2) * inv
    margin = np.minimum(np.minimum(u, v), 1 - u - v)
    hit = (np.abs(det) > 1e-12) & (margin >= 0) & (t > 0)
    return hit, t, margin


def rays_at(vertices, faces, n, seed):
    """Rays from random points around the mesh towards random triangles' centroids, and as
    many pointing away from the mesh (misses)."""
    rng = np.random.default_rng(seed)
    centre = vertices.mean(axis=0)
    radius = np.linalg.norm(vertices - centre, axis=1).max()
    origins = centre + rng.normal(size=(n, 3)) * 3 * radius
    targets = vertices[faces[rng.integers(0, len(faces), n)]].mean(axis=1)
    directions = targets - origins
    directions[n // 2:] *= -1
    return origins, directions


@pytest.mark.parametrize("mesh", [cube, sphere_arrays])
@pytest.mark.parametrize("kind", ["bvh", "kdtree", "irgrid"])
def test_trimesh_helpers_match_brute_force(mesh, kind):
    vertices, faces = mesh()
    origins, directions = rays_at(vertices, faces, 200, seed=11)
    hit, t, margin = brute_force(vertices, faces, origins, directions)
    # A ray that passes close to any triangle's edge may rightly pick its neighbour.
    clear = ~((np.abs(margin) < 1e-4) & (t > 0)).any(axis=1)
    intersector = lazytrace.RayMeshIntersector(type("Mesh", (), {"vertices": vertices, "faces": faces}),
                                               kind=kind, context=NATIVE)

    first = intersector.intersects_first(origins, directions)
    expected = np.where(hit.any(axis=1), np.argmin(np.where(hit, t, np.inf), axis=1), -1)
    assert np.array_equal(first[clear], expected[clear])
    assert np.array_equal(intersector.intersects_any(origins, directions)[clear], hit.any(axis=1)[clear])

    locations, index_ray, index_tri = intersector.intersects_location(origins, directions)
    for r in np.flatnonzero(clear):
        mine = index_tri[index_ray == r]
        theirs = np.flatnonzero(hit[r])
        assert sorted(mine) == sorted(theirs)
        order = theirs[np.argsort(t[r, theirs])]
        assert list(mine) == list(order)  # in order along the ray
        # The library traces the float32-rounded ray: at grazing angles that moves the point
        # along the surface by more than a float's rounding.
        points = origins[r] + t[r, order][:, None] * directions[r]
        assert np.allclose(locations[index_ray == r], points, atol=1e-4 * (1 + np.abs(origins[r]).max()))

    single = intersector.intersects_location(origins, directions, multiple_hits=False)
    assert np.array_equal(single[1], np.flatnonzero(first >= 0))
    assert np.array_equal(single[2], first[first >= 0])


def test_faces_with_nan_keep_their_numbers():
    vertices, faces = cube()
    vertices = np.vstack([vertices, [np.nan, 0, 0], [1e300, 0, 0]])
    faces = np.vstack([[[8, 1, 2], [9, 1, 2]], faces])  # a NaN vertex, one beyond float32
    scene = lazytrace.Scene.from_arrays(vertices, faces)
    assert scene.triangle_count == 12
    structure = lazytrace.Structure(scene, context=NATIVE)
    prim = structure.intersects_first([[0.3, 0.4, -1]], [[0, 0, 1]])
    assert prim[0] in (6, 12)  # the z = 0 face, as numbered by the caller


# ---- Persistence and statistics ----

def test_repeated_queries_build_only_what_is_new():
    scene = lazytrace.Scene.load("house-row:2")
    structure = lazytrace.Structure(scene, build="requested", stats=True, context=NATIVE)
    origins, directions = random_rays(scene, 100, seed=5)
    structure.intersect(origins[:50], directions[:50])
    first = structure.stats["nodes_built"]
    structure.intersect(origins[:50], directions[:50])
    assert structure.stats["nodes_built"] == first
    structure.intersect(origins[50:], directions[50:])
    stats = structure.stats
    assert stats["nodes_built"] >= first
    assert stats["rays"] == 150 and stats["structure"] == "bvh" and stats["build"] == "requested"
    assert stats["pool"]["tasks"] > 0 and stats["trace_ms"] > 0


def test_stats_without_collecting_still_describe_the_build():
    structure = lazytrace.Structure(lazytrace.Scene.load("cornell"), kind="lbvh", context=NATIVE)
    structure.intersect(np.zeros((4, 3)), np.ones((4, 3)))
    stats = structure.stats
    assert stats["structure"] == "lbvh" and stats["triangles"] > 0 and stats["nodes_built"] > 0
    assert stats["cells"] is None  # a group that does not apply, as in the JSON


# ---- Bad input ----

@pytest.fixture(scope="module")
def bvh():
    return lazytrace.Structure(lazytrace.Scene.load("sphere:1"), context=NATIVE)


def test_empty_batches(bvh):
    hits = bvh.intersect(np.empty((0, 3)), np.empty((0, 3)))
    assert all(len(a) == 0 for a in hits)
    assert bvh.occluded(np.empty((0, 3)), np.empty((0, 3))).shape == (0,)
    locations, index_ray, index_tri = bvh.intersects_location(np.empty((0, 3)), np.empty((0, 3)))
    assert locations.shape == (0, 3) and len(index_ray) == len(index_tri) == 0


def test_nan_zero_and_reversed_rays_miss(bvh):
    origins = np.array([[0, 0, -5], [np.nan, 0, -5], [0, 0, -5], [0, 0, -5], [np.inf, 0, 0]], float)
    directions = np.array([[0, 0, 1], [0, 0, 1], [0, 0, 0], [0, 0, 1], [0, 0, 1]], float)
    t, prim, _, _ = bvh.intersect(origins, directions, tmin=[0, 0, 0, 9, 0], tmax=[np.inf, np.inf, 1, 1, 9])
    assert prim[0] >= 0 and (prim[1:] == -1).all() and np.isinf(t[1:]).all()


def test_one_origin_for_many_directions(bvh):
    directions = np.random.default_rng(1).normal(size=(50, 3))
    assert (bvh.intersects_first([0, 0, 0], directions) >= 0).all()  # from inside the sphere


@pytest.mark.parametrize("origins,directions,error", [
    (np.zeros((4, 2)), np.zeros((4, 3)), ValueError),
    (np.zeros((4, 3)), np.zeros((5, 3)), ValueError),
    (np.zeros((2, 3, 3)), np.zeros((2, 3)), ValueError),
    (np.array([["a", "b", "c"]]), np.zeros((1, 3)), TypeError),
    ([[0, 0], [0, 0, 0]], np.zeros((2, 3)), ValueError),
])
def test_bad_ray_arrays_raise(bvh, origins, directions, error):
    with pytest.raises(error):
        bvh.intersect(origins, directions)


def test_bad_tmax_raises(bvh):
    with pytest.raises(ValueError, match="tmax"):
        bvh.intersect(np.zeros((3, 3)), np.ones((3, 3)), tmax=[1, 2])


def test_bad_meshes_raise():
    vertices, faces = cube()
    with pytest.raises(ValueError, match="faces"):
        lazytrace.Scene.from_arrays(vertices, faces + 8)
    with pytest.raises(ValueError, match="vertices"):
        lazytrace.Scene.from_arrays(vertices[:, :2], faces)
    with pytest.raises(TypeError, match="faces"):
        lazytrace.Scene.from_arrays(vertices, faces.astype(float))
    empty = lazytrace.Scene.from_arrays(np.empty((0, 3)), np.empty((0, 3), int))
    with pytest.raises(lazytrace.LazytraceError, match="no triangles") as caught:
        lazytrace.Structure(empty, context=NATIVE)
    assert caught.value.name == "LT_ERROR_EMPTY_SCENE"


def test_library_errors_carry_its_message(tmp_path):
    with pytest.raises(lazytrace.LazytraceError, match="unknown generator 'nope'"):
        lazytrace.Scene.load("nope:1")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(lazytrace.LazytraceError, match="bad.obj") as caught:
        lazytrace.Scene.load(str(bad))
    assert ":3" in str(caught.value)  # the line
    scene = lazytrace.Scene.load("cornell")
    with pytest.raises(lazytrace.LazytraceError, match="unknown structure 'octree'"):
        lazytrace.Structure(scene, kind="octree", context=NATIVE)
    with pytest.raises(lazytrace.LazytraceError, match="--leaf-size"):
        lazytrace.Structure(scene, leaf_size=0, context=NATIVE)
    with pytest.raises(ValueError, match="device"):
        lazytrace.Context("gpu")


def test_scene_files_and_options(tmp_path):
    mesh = tmp_path / "quad.obj"
    mesh.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n")
    scene = lazytrace.Scene.load(str(mesh))
    assert scene.triangle_count == 2
    description = tmp_path / "two.json"
    description.write_text('{"meshes": [{"file": "quad.obj"}, {"generator": "sphere:1"}],'
                           ' "instances": [{"mesh": 0}, {"mesh": 1, "translate": [0, 0, 5]}]}')
    assert lazytrace.Scene.load(str(description)).triangle_count == 2 + 80
    for kind, options in [("bvh", {"leaf_size": 1, "bins": 4}), ("grid", {"grid_density": 2}),
                          ("kdtree", {"traversal": "backtrack", "build": "full"}),
                          ("irgrid", {"merge": "off", "intersect": "fast"})]:
        structure = lazytrace.Structure(scene, kind=kind, context=NATIVE, **options)
        t, prim, u, v = structure.intersect([[0.5, 0.2, 2]], [[0, 0, -1]])
        assert t[0] == 2 and prim[0] in (0, 1)
