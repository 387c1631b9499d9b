/* penumbra's C API: scenes (glTF/GLB models, JSON scene files, built-in scenes) and the plain structs for cameras and
 * lights, with their command-line forms. A scene is immutable once loaded. */
#ifndef PENUMBRA_SCENE_H
#define PENUMBRA_SCENE_H

#include "penumbra/status.h"

/** @file
 *  Scenes, cameras and lights. */

#ifdef __cplusplus
extern "C" {
#endif

/** A camera, Y up, right-handed, looking from `eye` to `target`. Plain data: pn_camera_init() it first (which sets
 *  `size`), then set fields, parse (pn_camera_parse()) or take one from a scene (pn_scene_camera()). */
typedef struct pn_camera {
  size_t size; /**< sizeof(pn_camera) as the caller compiled it (set by pn_camera_init()): every call that reads or
                  fills a camera requires it; fields a later version adds go after these and are read and written
                  only where `size` holds them. */
  float eye[3];            /**< Position. */
  float target[3];         /**< The point it looks at (not `eye`). */
  float up[3];             /**< Preferred up direction (replaced when parallel to the view). */
  int orthographic;        /**< 0: perspective (`fov_y_deg`), 1: orthographic (`ortho_half_height`). */
  float fov_y_deg;         /**< Perspective: vertical field of view, degrees, in (0, 180). */
  float ortho_half_height; /**< Orthographic: half the view's height, world units. */
  float clip_near;         /**< View-space near clip distance; 0: none beyond the fit to the scene. */
  float clip_far;          /**< View-space far clip distance; INFINITY: none. */
  int width;               /**< Image width, pixels (1..8192, the rasterizer's limit). */
  int height;              /**< Image height, pixels (1..8192). */
} pn_camera;

/** The type of a light. */
typedef enum pn_light_type {
  PN_LIGHT_SPOT = 0,        /**< A spot at `position` aiming at `target`; `radius` > 0: a disk area light. */
  PN_LIGHT_DIRECTIONAL = 1, /**< Light travelling along `direction`; `angular_radius_deg` > 0: a sun disk. */
  PN_LIGHT_POINT = 2,       /**< A point at `position` (`radius` > 0: a sphere), shadowed as six cube faces. */
  PN_LIGHT_TYPE_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller passes
                                         is one of its values (and refused). */
} pn_light_type;

/** A light. Plain data: pn_light_init() it first (which sets `size`), then set fields, parse (pn_light_parse()) or
 *  take one from a scene (pn_scene_light()). */
typedef struct pn_light {
  size_t size; /**< sizeof(pn_light) as the caller compiled it (set by pn_light_init()): every call that reads or fills
                  a light requires it; fields a later version adds go after these and are read and written only where
                  `size` holds them. */
  pn_light_type type;       /**< Spot, directional or point. */
  const char* name;         /**< Its name (NULL or "": unnamed, layer "light"). A scene's: valid while it lives. */
  float position[3];        /**< Spot and point: position. */
  float target[3];          /**< Spot: the point it aims at. */
  float fov_deg;            /**< Spot: full cone angle, degrees, in (0, 180). */
  float radius;             /**< Spot: disk radius; point: sphere radius; 0: a point source. */
  float inner_fov_deg;      /**< Spot: full angle of the fully lit inner cone (glTF); negative: none. */
  float range;              /**< Spot and point: glTF range (the preview fades out towards it); 0: unlimited. */
  float direction[3];       /**< Directional: the unit direction the light travels. */
  float angular_radius_deg; /**< Directional: angular radius of the sun disk, degrees, in [0, 45). */
} pn_light;

/** How a scene is loaded (pn_scene_load_options_init() gives the defaults). */
typedef struct pn_scene_load_options {
  size_t size; /**< sizeof(pn_scene_load_options) as the caller compiled it (set by pn_scene_load_options_init()):
                  fields a later version adds go after these and are read only when `size` holds them. */
  int has_time;          /**< Non-zero: evaluate glTF animations at `time`; 0: the file's static pose. */
  double time;           /**< Seconds (with `has_time`). */
  const char* animation; /**< With `has_time`: the one animation to play, by index or name; NULL or "": all. */
} pn_scene_load_options;

/** One mesh of the caller's own geometry (pn_scene_create); pn_mesh_init() gives the defaults. The arrays are
 *  read during the call only. */
typedef struct pn_mesh {
  size_t size;             /**< sizeof(pn_mesh) as the caller compiled it (set by pn_mesh_init()): fields a later
                               version adds go after these and are read only when `size` holds them. */
  const float* positions;  /**< x, y, z per vertex. */
  size_t vertex_count;     /**< Vertices in `positions` (and `normals`). */
  const float* normals;    /**< x, y, z per vertex, or NULL: the area-weighted normals of the triangles. */
  const uint32_t* indices; /**< Three vertex indices per triangle, counter-clockwise front faces. */
  size_t triangle_count;   /**< Triangles in `indices`. */
  const float* transform;  /**< 16 floats, column-major (as OpenGL, GLM and glTF), to world space; NULL: identity. */
  const char* name;        /**< The mesh's object name; NULL or "": "mesh N" (N its index in the call). */
  int double_sided;        /**< Non-zero (the default): both sides seen; 0: back faces culled in the camera's view. */
} pn_mesh;

/** A loaded scene: world-space triangles with normals, the cameras and lights it names. Reference counted like
 *  pn_context; immutable, so any number of threads may read it. */
typedef struct pn_scene pn_scene;

/** The defaults: eye (0, 1, 5), target the origin, up +Y, perspective with a 45 degree fov, 1280x720; `size` is
 *  sizeof(pn_camera). */
PN_API void pn_camera_init(pn_camera* camera);
/** Parses "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]" (the CLI's --camera) into `camera`, which pn_camera_init() prepared (its
 *  `size` is kept; the image size becomes the default). */
PN_API pn_status pn_camera_parse(const char* spec, pn_camera* camera);

/** The defaults: an unnamed spot at (0, 10, 0) aiming at the origin with a 60 degree cone; `size` is
 *  sizeof(pn_light). */
PN_API void pn_light_init(pn_light* light);
/** Parses "spot:PX,PY,PZ:TX,TY,TZ:FOV[:RADIUS]", "dir:DX,DY,DZ[:ANGLE]" or "point:PX,PY,PZ[:RADIUS]" (the CLI's
 *  --light) into an unnamed light, which pn_light_init() prepared (its `size` is kept). */
PN_API pn_status pn_light_parse(const char* spec, pn_light* light);

/** No animation time, every animation. */
PN_API void pn_scene_load_options_init(pn_scene_load_options* options);

/** Loads "builtin:NAME[:key=value,...]", a .json scene file or a .gltf/.glb model (`options` may be NULL).
 *  PN_ERROR_SCENE names the file and the element at fault. */
PN_API pn_status pn_scene_load(const char* spec, const pn_scene_load_options* options, pn_scene** scene);
/** The defaults: no arrays, no transform, no name, double-sided. */
PN_API void pn_mesh_init(pn_mesh* mesh);
/** A scene of the caller's own triangles (`meshes`, each its own object) and lights (`lights`, may be NULL when
 *  `light_count` is 0; unnamed ones become "light<I>", as a scene file's). It has no cameras: the default camera
 *  frames the geometry. Positions that are not finite, indices out of range and counts over the loader's limits
 *  are PN_ERROR_SCENE naming the mesh and the element; frames record "penumbra:scene" as "meshes (M meshes, T
 *  triangles)". */
PN_API pn_status pn_scene_create(const pn_mesh* meshes, size_t mesh_count, const pn_light* lights, size_t light_count,
                                 pn_scene** scene);
/** Adds a reference. */
PN_API pn_status pn_scene_retain(pn_scene* scene);
/** Drops a reference; frees the scene at 0 (a renderer keeps its own). NULL is a no-op. */
PN_API pn_status pn_scene_release(pn_scene* scene);

/** Triangles after instancing. 0 for NULL. */
PN_API size_t pn_scene_triangle_count(const pn_scene* scene);
/** The world-space bounding box of the geometry (min > max for an empty scene). */
PN_API pn_status pn_scene_bounds(const pn_scene* scene, float min[3], float max[3]);
/** Cameras the scene names (a scene file's, a built-in scene's, a glTF file's in node order). */
PN_API size_t pn_scene_camera_count(const pn_scene* scene);
/** Camera `index` (< pn_scene_camera_count()), into `camera` as pn_camera_init() prepared it (every call that fills
 *  a camera or a light keeps its `size` and writes only what it holds). */
PN_API pn_status pn_scene_camera(const pn_scene* scene, size_t index, pn_camera* camera);
/** The camera a frame uses by default, as the CLI does: the scene's first, else a view framing the scene. */
PN_API pn_status pn_scene_default_camera(const pn_scene* scene, pn_camera* camera);
/** Lights the scene names (their names unique and channel-safe). */
PN_API size_t pn_scene_light_count(const pn_scene* scene);
/** Light `index` (< pn_scene_light_count()); its name points into the scene. */
PN_API pn_status pn_scene_light(const pn_scene* scene, size_t index, pn_light* light);
/** The soft spot light above the scene that a frame uses when the scene has no lights (unnamed). */
PN_API pn_status pn_scene_framing_light(const pn_scene* scene, pn_light* light);

#ifdef __cplusplus
}
#endif

#endif
