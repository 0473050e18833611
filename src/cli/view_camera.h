/* view_camera.h: the camera `trazador view` moves with the mouse (orbit about a point of the
 * scene, pan, dolly), computed in double and rounded once to the floats a scene holds, and the
 * scene line that gives it back. */
#ifndef TRAZADOR_VIEW_CAMERA_H
#define TRAZADOR_VIEW_CAMERA_H

#include <stddef.h>

#include "scene/scene.h"

/* The scene's camera fields the view changes. */
typedef struct view_camera {
    vec3 position, direction, up;
} view_camera;

/* A drag: the camera and the point it turns about when it began. */
typedef struct view_drag {
    view_camera start;
    double pivot[3];
} view_drag;

/* The camera of scene s; never fails. */
view_camera view_camera_of(const scene *s);
/* Starts a drag from camera c of scene s: the pivot is where the centre ray first meets a
 * sphere or a face, else a point ahead at the distance of the scene's middle; never fails. */
view_drag view_camera_drag(const scene *s, view_camera c);
/* The camera orbited about the drag's pivot by dx, dy pixels of mouse travel since it began
 * (up stays the scene's up; the camera looks at most 89 degrees up or down); never fails. */
view_camera view_camera_orbit(const view_drag *d, int dx, int dy);
/* The camera moved across the view so that the pivot follows the mouse by dx, dy pixels of
 * scene s; never fails. */
view_camera view_camera_pan(const scene *s, const view_drag *d, int dx, int dy);
/* The camera moved along its direction, toward the pivot for steps > 0 (each step a fifth of
 * the way), away for steps < 0; never fails. */
view_camera view_camera_dolly(const view_drag *d, int steps);
/* Writes the `camera` line of camera c with scene s's fov and near (when set), every number
 * with the digits a float needs to read back as itself; the snprintf count. */
int view_camera_line(const scene *s, view_camera c, char *out, size_t size);

#endif
