/* Mesh formats other than OBJ and PLY (.gltf, .glb, .stl, .off, ...) through assimp's C API.
 * Triangle numbering is the order assimp hands the triangles over: meshes in order, faces in
 * order within each mesh, after assimp has triangulated polygons and applied node transforms. */
#include "scene_internal.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "runtime/error.h"

/* Triangulate splits polygons; PreTransformVertices bakes the node transforms into the vertices,
 * so a mesh placed by the node graph lands where the file puts it. Steps that reorder or merge
 * vertices and faces (JoinIdenticalVertices, SortByPType, ...) are left out, so the order stays
 * the file's as far as assimp allows. */
/* ValidateDataStructure runs first and turns a malformed file (a truncated binary PLY: a face
 * indexing vertices that were never read) into an import error, where the steps after it
 * would read out of bounds and crash. Polygons are fanned here, (v0, vi, vi+1) as for OBJ,
 * rather than by assimp's Triangulate step, which aborts the process on some malformed
 * faces (an assertion, found by fuzzing PLY input). */
#define IMPORT_FLAGS (aiProcess_ValidateDataStructure | aiProcess_PreTransformVertices)

static void copy_vertex(const struct aiVector3D *v, float out[3]) {
  out[0] = (float)v->x;
  out[1] = (float)v->y;
  out[2] = (float)v->z;
}

/* Appends a mesh's triangles, polygons fanned from their first vertex; points and lines that
 * the file mixes in are skipped. */
static lt_status add_mesh(const char *path, unsigned mesh_index, const struct aiMesh *mesh, lt_scene *scene) {
  for (unsigned i = 0; i < mesh->mNumFaces; i++) {
    const struct aiFace *face = &mesh->mFaces[i];
    if (face->mNumIndices < 3 || !face->mIndices) continue;

    /* Importers are not all careful with indices; a bad one must not read past the vertices. */
    for (unsigned k = 0; k < face->mNumIndices; k++)
      if (face->mIndices[k] >= mesh->mNumVertices)
        return lt__fail(LT_ERROR_PARSE, "%s: mesh %u face %u: vertex index %u out of range (%u vertices)", path,
                        mesh_index, i, face->mIndices[k], mesh->mNumVertices);
    float p[3][3];
    copy_vertex(&mesh->mVertices[face->mIndices[0]], p[0]);
    for (unsigned k = 1; k + 1 < face->mNumIndices; k++) {
      copy_vertex(&mesh->mVertices[face->mIndices[k]], p[1]);
      copy_vertex(&mesh->mVertices[face->mIndices[k + 1]], p[2]);
      lt_status status = lt__scene_add_tri(scene, p[0], p[1], p[2]);
      if (status) return status;
    }
  }
  return LT_OK;
}

/* What lazytrace checks before it hands an OFF file to assimp, whose reader allocates for the
 * counts the header declares before it reads a byte of the body (found by fuzzing, as with PLY,
 * which lazytrace now reads itself: a 200-byte file claiming 10^9 vertices). Every declared
 * vertex or face takes at least 2 bytes of the body (a digit and a separator), so counts beyond
 * half the file's size are refused. */
static lt_status check_header(const char *path, FILE *f, long size) {
  char line[256];
  double declared = 0, count, faces;
  if (!fgets(line, sizeof line, f) || strncmp(line, "OFF", 3) != 0) return LT_OK;

  /* The counts stand after "OFF" on its line, or on the first line after it that is neither
   * blank nor a comment. */
  if (sscanf(line + 3, "%lf %lf", &count, &faces) == 2) declared = count + faces;
  else
    for (int n = 1; n < 256 && fgets(line, sizeof line, f); n++) {
      line[strcspn(line, "\r\n")] = '\0';
      if (line[0] == '#' || line[0] == '\0') continue;
      if (sscanf(line, "%lf %lf", &count, &faces) == 2) declared = count + faces;
      break;
    }
  if (declared > (double)size / 2)
    return lt__fail(LT_ERROR_PARSE, "%s: the header declares %.0f vertices and faces, more than a file of %ld bytes can hold",
                    path, declared, size);
  return LT_OK;
}

lt_status lt__load_assimp(const char *path, lt_scene *scene) {
  if (!path || !scene) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__load_assimp: NULL argument");

  /* assimp reports a missing file as a generic import failure, so check it here to return
   * LT_ERROR_IO with the system's reason. */
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
  rewind(f);
  lt_status checked = size >= 0 ? check_header(path, f, size) : LT_OK;
  fclose(f);
  if (checked) return checked;

  const struct aiScene *ai = aiImportFile(path, IMPORT_FLAGS);
  if (!ai) return lt__fail(LT_ERROR_PARSE, "%s: %s", path, aiGetErrorString());

  lt_status status = LT_OK;
  for (unsigned m = 0; m < ai->mNumMeshes && !status; m++) status = add_mesh(path, m, ai->mMeshes[m], scene);
  aiReleaseImport(ai);
  return status;
}
