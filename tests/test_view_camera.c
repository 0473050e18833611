/* test_view_camera.c: the camera moves of `trazador view` (src/cli/view_camera.c), without a
 * window: the drag's pivot is where the centre ray meets the scene; an orbit keeps the camera's
 * distance to it and looks at it; a pan moves the camera across the view by the pixel's size at
 * the pivot; a wheel step goes a fifth of the way; and the camera line reads back as the very
 * floats it printed, fov and near included. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "cli/view_camera.h"
#include "scene/scene.h"

/* cornell.scene's box: the back wall's inner face at z = 3, the camera at z = -9.5. */
static const char box[] =
    "camera position 0 0 -9.5 direction 0 0 1 up 0 1 0\n"
    "plane width 4 height 4 pixel 0.01\n"
    "light position 0 1.6 0.6 power 9\n"
    "sphere lambertian center 0 0 100003 radius 100000 color 0.75 0.75 0.75\n";

static bool parse(const char *text, scene *s) {
    scene_error err;
    bool ok = scene_parse_string(text, strlen(text), "view.scene", s, &err);
    CHECK(ok, "%s:%d:%d: %s", err.file, err.line, err.col, err.message);
    return ok;
}

static double distance(vec3 a, const double b[3]) {
    double x = a.x - b[0], y = a.y - b[1], z = a.z - b[2];
    return sqrt(x * x + y * y + z * z);
}

static void test_moves(void) {
    scene s;
    if (!parse(box, &s)) return;
    view_camera c = view_camera_of(&s);
    view_drag d = view_camera_drag(&s, c);
    EXPECT(fabs(d.pivot[0]) < 1e-9 && fabs(d.pivot[1]) < 1e-9 && fabs(d.pivot[2] - 3.0) < 1e-6);
    /* An orbit keeps the distance to the pivot and looks at it. */
    view_camera o = view_camera_orbit(&d, 40, -25);
    double r = distance(o.position, d.pivot);
    EXPECT(fabs(r - 12.5) < 1e-5);
    double to[3] = {d.pivot[0] - o.position.x, d.pivot[1] - o.position.y,
                    d.pivot[2] - o.position.z};
    double dot = (to[0] * o.direction.x + to[1] * o.direction.y + to[2] * o.direction.z) / r;
    EXPECT(dot > 1.0 - 1e-6);
    EXPECT(o.position.x != 0.0f && o.position.y != 0.0f && !memcmp(&o.up, &c.up, sizeof o.up));
    /* Far past the pole, the camera stops at 89 degrees, either way. */
    double steepest = sin(89.0 * 3.14159265358979323846 / 180.0);
    EXPECT(fabs(view_camera_orbit(&d, 0, 100000).direction.y + steepest) < 1e-6);
    EXPECT(fabs(view_camera_orbit(&d, 0, -100000).direction.y - steepest) < 1e-6);
    /* A pan of 10 pixels right moves the camera 10 pixels' worth left at the pivot's depth:
     * 0.01 x 12.5 / 8 a pixel (the plane 2 x width = 8 away). */
    view_camera p = view_camera_pan(&s, &d, 10, 0);
    EXPECT(fabs(p.position.x + 10 * 0.01 * 12.5 / 8.0) < 1e-6 && p.position.y == 0.0f);
    EXPECT(!memcmp(&p.direction, &c.direction, sizeof p.direction));
    /* A wheel step in goes a fifth of the way to the pivot, one out comes back a quarter. */
    EXPECT(fabs(view_camera_dolly(&d, 1).position.z - (-9.5 + 2.5)) < 1e-6);
    EXPECT(fabs(view_camera_dolly(&d, -1).position.z - (-9.5 - 12.5 * 0.25)) < 1e-6);
    scene_free(&s);
}

/* The line of an orbited camera, with fov and near, parses back to the same floats. */
static void test_line(void) {
    static const char fov[] =
        "camera position 0 0 -9.5 direction 0 0 1 up 0 1 0 fov 37.5 near 0.25\n"
        "plane width 4 height 4 pixel 0.01\n"
        "sphere lambertian center 0 0 100003 radius 100000 color 0.75 0.75 0.75\n";
    scene s, back;
    if (!parse(fov, &s)) return;
    view_drag d = view_camera_drag(&s, view_camera_of(&s));
    view_camera c = view_camera_orbit(&d, 33, 17);
    char text[1024];
    int n = view_camera_line(&s, c, text, 512);
    EXPECT(n > 0 && n < 512 && strstr(text, " fov 37.5 near 0.25"));
    strcat(text, "\nplane width 4 height 4 pixel 0.01\n");
    if (!parse(text, &back)) {
        scene_free(&s);
        return;
    }
    EXPECT(!memcmp(&back.camera_position, &c.position, sizeof c.position));
    EXPECT(!memcmp(&back.camera_direction, &c.direction, sizeof c.direction));
    EXPECT(!memcmp(&back.camera_up, &c.up, sizeof c.up));
    EXPECT(back.camera_fov == s.camera_fov && back.camera_near == s.camera_near);
    scene_free(&back);
    scene_free(&s);
}

int main(void) {
    CHECK_CASE(test_moves);
    CHECK_CASE(test_line);
    return check_summary("test_view_camera");
}
