/* Mesh formats other than OBJ (.ply, .gltf, .glb, .stl, .off, ...) through assimp's C API.
 * Triangle numbering is the order assimp hands the triangles over: meshes in order, faces in
 * order within each mesh, after assimp has triangulated polygons and applied node transforms. */
#include "scene_internal.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "../runtime/error.h"

/* Triangulate splits polygons; PreTransformVertices bakes the node transforms into the vertices,
 * so a mesh placed by the node graph lands where the file puts it. Steps that reorder or merge
 * vertices and faces (JoinIdenticalVertices, SortByPType, ...) are left out, so the order stays
 * the file's as far as assimp allows. */
#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_PreTransformVertices)

static void copy_vertex(const struct aiVector3D *v, float out[3]) {
  out[0] = (float)v->x;
  out[1] = (float)v->y;
  out[2] = (float)v->z;
}

/* Appends a mesh's triangles; points and lines that the file mixes in are skipped. */
static lt_status add_mesh(const char *path, unsigned mesh_index, const struct aiMesh *mesh, lt_scene *scene) {
  for (unsigned i = 0; i < mesh->mNumFaces; i++) {
    const struct aiFace *face = &mesh->mFaces[i];
    if (face->mNumIndices != 3) continue;

    /* Importers are not all careful with indices; a bad one must not read past the vertices. */
    float p[3][3];
    for (int k = 0; k < 3; k++) {
      unsigned index = face->mIndices[k];
      if (index >= mesh->mNumVertices)
        return lt__fail(LT_ERROR_PARSE, "%s: mesh %u face %u: vertex index %u out of range (%u vertices)", path,
                        mesh_index, i, index, mesh->mNumVertices);
      copy_vertex(&mesh->mVertices[index], p[k]);
    }
    lt_status status = lt__scene_add_tri(scene, p[0], p[1], p[2]);
    if (status) return status;
  }
  return LT_OK;
}

lt_status lt__load_assimp(const char *path, lt_scene *scene) {
  if (!path || !scene) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__load_assimp: NULL argument");

  /* assimp reports a missing file as a generic import failure, so check it here to return
   * LT_ERROR_IO with the system's reason. */
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  fclose(f);

  const struct aiScene *ai = aiImportFile(path, IMPORT_FLAGS);
  if (!ai) return lt__fail(LT_ERROR_PARSE, "%s: %s", path, aiGetErrorString());

  lt_status status = LT_OK;
  for (unsigned m = 0; m < ai->mNumMeshes && !status; m++) status = add_mesh(path, m, ai->mMeshes[m], scene);
  aiReleaseImport(ai);
  return status;
}
