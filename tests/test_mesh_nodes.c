/* test_mesh_nodes.c: a model file whose nodes place one mesh several times (glTF, COLLADA) keeps
 * that mesh's faces once and makes an instance per node (DESIGN section 3.4). Against the same
 * file with the mesh written once per node (which loads as faces): identity nodes give the very
 * bits, moved, turned, scaled, mirrored and nested ones the image within the bound of
 * test_instances; the reference and packet builds agree; `trazador info` counts unique faces and
 * instances; emitters and mirrored glass stay flattened; a singular node is skipped with a
 * warning, one that moves the mesh past the coordinate range is an error. With the argument
 * `vulkan`: every Vulkan walk the device has renders the CPU back end's bits (exit 77 only without
 * a Vulkan device). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh_test.h"
#include "render/vk/vk_context.h"
#include "scene/model_scene.h"
#include "tmp_dir.h"

/* The bumpy sphere of test_instances: 2 segments (rings - 1) faces. */
#define RINGS 21
#define SEGMENTS 20
#define FACES (2 * SEGMENTS * (RINGS - 1))

/* Writes name.bin (float corners, then uint32 indices) and name.gltf: `meshes` meshes that all
 * read those, mesh 0 of material 0 when materials is given, the nodes and the scene's root
 * nodes as JSON. */
static void write_gltf(const char *name, int meshes, const char *nodes, const char *roots,
                       const char *materials) {
    const double pi = 3.14159265358979323846;
    enum { VERTICES = 2 + (RINGS - 1) * SEGMENTS };
    static float pos[VERTICES][3];
    static unsigned idx[FACES][3];
    pos[0][1] = 1, pos[1][1] = -1;
    for (int r = 1; r < RINGS; r++)
        for (int s = 0; s < SEGMENTS; s++) {
            double t = pi * r / RINGS, p = 2 * pi * s / SEGMENTS, bump = 1.0 + 0.2 * sin(5 * p);
            float *v = pos[2 + (r - 1) * SEGMENTS + s];
            v[0] = (float)(sin(t) * cos(p) * bump), v[1] = (float)cos(t);
            v[2] = (float)(sin(t) * sin(p) * bump);
        }
#define RING(r, s) (2u + ((unsigned)(r)-1u) * SEGMENTS + ((unsigned)(s) % SEGMENTS))
    int f = 0;
    for (int s = 0; s < SEGMENTS; s++) {
        idx[f][0] = 0, idx[f][1] = RING(1, s + 1), idx[f++][2] = RING(1, s);
        idx[f][0] = 1, idx[f][1] = RING(RINGS - 1, s), idx[f++][2] = RING(RINGS - 1, s + 1);
        for (int r = 1; r < RINGS - 1; r++) {
            unsigned a = RING(r, s), b = RING(r, s + 1), c = RING(r + 1, s + 1), d = RING(r + 1, s);
            idx[f][0] = a, idx[f][1] = b, idx[f++][2] = c;
            idx[f][0] = a, idx[f][1] = c, idx[f++][2] = d;
        }
    }
#undef RING
    char bin_name[64], path[64];
    snprintf(bin_name, sizeof bin_name, "%s.bin", name);
    static char bin[sizeof pos + sizeof idx];
    memcpy(bin, pos, sizeof pos);
    memcpy(bin + sizeof pos, idx, sizeof idx);
    tmp_file_write(tmp_path(bin_name), bin, sizeof bin);
    char mesh_list[4096] = "";
    for (int k = 0; k < meshes; k++) {
        size_t n = strlen(mesh_list);
        snprintf(mesh_list + n, sizeof mesh_list - n,
                 "%s{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1%s}]}",
                 k ? "," : "", materials && k == 0 ? ",\"material\":0" : "");
    }
    char *gltf = malloc(1 << 16);
    snprintf(gltf, 1 << 16,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[%s]}],"
             "\"nodes\":[%s],\"meshes\":[%s],%s%s%s\"buffers\":[{\"uri\":\"%s\","
             "\"byteLength\":%zu}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],\"accessors\":[{"
             "\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\","
             "\"min\":[-1.2,-1,-1.2],\"max\":[1.2,1,1.2]},{\"bufferView\":1,\"componentType\":"
             "5125,\"count\":%d,\"type\":\"SCALAR\"}]}\n",
             roots, nodes, mesh_list, materials ? "\"materials\":[" : "",
             materials ? materials : "", materials ? "]," : "", bin_name, sizeof bin, sizeof pos,
             sizeof pos, sizeof idx, VERTICES, 3 * FACES);
    snprintf(path, sizeof path, "%s.gltf", name);
    write_text(path, gltf);
    free(gltf);
}

/* Node k of a list placing mesh k (flat) or mesh 0 (shared), with the transform given. */
static void node(char *out, size_t size, bool flat, int k, const char *transform) {
    size_t n = strlen(out);
    snprintf(out + n, size - n, "%s{\"name\":\"n%d\",\"mesh\":%d%s%s}", k ? "," : "", k,
             flat ? k : 0, transform[0] ? "," : "", transform);
}

/* The moved nodes: identity, translation, rotation, non-uniform scale, a mirror and a child
 * (node 6) of a turned parent (node 5), each placing the mesh. */
static const char *const moved_nodes[] = {
    "",
    "\"translation\":[2.5,0,0]",
    "\"translation\":[-2.5,0.5,1],\"rotation\":[0,0.3826834,0,0.9238795]",
    "\"translation\":[0,0.3,3],\"scale\":[1.5,0.5,1]",
    "\"translation\":[2.5,0,3],\"scale\":[-1,1,1]",
    "\"translation\":[-2.5,0,-3],\"rotation\":[0.258819,0,0,0.9659258],\"children\":[6]",
    "\"translation\":[0,1.5,0],\"scale\":[0.5,0.5,0.5]",
};
#define MOVED 7

/* Writes name.gltf with the moved nodes, the mesh shared or written once per node. */
static void write_moved(const char *name, bool flat) {
    char nodes[4096] = "";
    for (int k = 0; k < MOVED; k++) node(nodes, sizeof nodes, flat, k, moved_nodes[k]);
    write_gltf(name, flat ? MOVED : 1, nodes, "0,1,2,3,4,5", NULL);
}

static const char *header =
    "camera position 0 6 -14 direction 0 -0.45 1\nplane width 2 height 1.5 pixel 0.02\n"
    "light position -4 9 -6 power 300\nsphere lambertian center 0 -1001 0 radius 1000 color 0.7 "
    "0.7 0.7\nrender samples 2\n";

/* Parses header + `mesh file NAME` + extra; false (reported) on failure. */
static bool parse_model(const char *name, const char *extra, scene *s) {
    char text[2048];
    snprintf(text, sizeof text, "%smesh file %s%s\n", header, name, extra);
    scene_error err;
    bool ok = parse(text, 1, s, &err);
    CHECK(ok, "%s: %s", name, err.message);
    return ok;
}

/* Two identity nodes sharing the mesh against the mesh written twice: the same bits. */
static void test_identity(void) {
    char nodes[512] = "";
    node(nodes, sizeof nodes, false, 0, "");
    node(nodes, sizeof nodes, false, 1, "");
    write_gltf("same", 1, nodes, "0,1", NULL);
    nodes[0] = '\0';
    node(nodes, sizeof nodes, true, 0, "");
    node(nodes, sizeof nodes, true, 1, "");
    write_gltf("same_flat", 2, nodes, "0,1", NULL);
    scene inst, flat;
    if (!parse_model("same.gltf", "", &inst)) return;
    if (!parse_model("same_flat.gltf", "", &flat)) {
        scene_free(&inst);
        return;
    }
    CHECK(inst.instance_count == 2 && inst.model_face_count == FACES && inst.triangle_count == 0,
          "identity: %d instances, %d model faces, %d faces", inst.instance_count,
          inst.model_face_count, inst.triangle_count);
    CHECK(flat.instance_count == 0 && flat.triangle_count == 2 * FACES,
          "identity flattened: %d instances, %d faces", flat.instance_count, flat.triangle_count);
    film a = {0}, b = {0}, r = {0};
    CHECK(render_with(&inst, NULL, &a) && render_with(&flat, NULL, &b) &&
              render_with(&inst, "reference", &r),
          "identity: a render failed");
    CHECK(same_film(&a, &b), "identity nodes differ from the mesh written per node");
    CHECK(same_film(&a, &r), "identity: the packet build differs from the reference");
    film_free(&a), film_free(&b), film_free(&r);
    scene_free(&inst), scene_free(&flat);
}

/* Moved, turned, scaled, mirrored and nested nodes against the mesh written per node: the
 * bound of test_instances (rays moved into an instance's space round differently). */
static void test_moved(void) {
    write_moved("moved", false);
    write_moved("moved_flat", true);
    scene inst, flat;
    if (!parse_model("moved.gltf", "", &inst)) return;
    if (!parse_model("moved_flat.gltf", "", &flat)) {
        scene_free(&inst);
        return;
    }
    CHECK(
        inst.instance_count == MOVED && inst.model_face_count == FACES && inst.triangle_count == 0,
        "moved: %d instances, %d model faces, %d faces", inst.instance_count, inst.model_face_count,
        inst.triangle_count);
    CHECK(flat.triangle_count == MOVED * FACES, "moved flattened: %d faces", flat.triangle_count);
    film a = {0}, b = {0}, r = {0}, v = {0};
    CHECK(render_with(&inst, NULL, &a) && render_with(&flat, NULL, &b) &&
              render_with(&inst, "reference", &r) && render_with(&inst, "avx2", &v),
          "moved: a render failed");
    CHECK(same_film(&a, &r) && same_film(&a, &v),
          "moved: the packet builds differ from the reference");
    if (a.accum && b.accum) {
        int n = a.width * a.height, differ = 0;
        double diff = 0.0, sum = 0.0;
        for (int k = 0; k < n; k++)
            for (int c = 0; c < 3; c++) {
                double x = a.accum[4 * k + c] / a.accum[4 * k + 3];
                double y = b.accum[4 * k + c] / b.accum[4 * k + 3];
                diff += fabs(x - y), sum += y;
                differ += fabs(x - y) > 1e-3 * (1.0 + y) && c == 0;
            }
        printf("moved nodes: %d of %d pixels differ, mean difference %.3g of the mean\n", differ, n,
               diff / sum);
        CHECK(differ <= n / 50 && diff <= 2e-3 * sum,
              "moved: %d of %d pixels differ, mean difference %.3g of the mean", differ, n,
              diff / sum);
        CHECK(sum > 0.0, "moved: a black image");
    }
    film_free(&a), film_free(&b), film_free(&r), film_free(&v);
    scene_free(&inst), scene_free(&flat);
}

/* `trazador info` (model_scene_list) and the model given as the scene count unique faces and
 * instances. */
static void test_counts(void) {
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    scene_error err;
    bool ok = out && model_scene_list(tmp_path("moved.gltf"), out, &err);
    if (out) fclose(out);
    char want[160];
    snprintf(want, sizeof want,
             "%d faces (%d unique: 0 placed once, %d in 1 meshes that %d instances share)",
             MOVED * FACES, FACES, FACES, MOVED);
    CHECK(ok && text && strstr(text, want), "info: %s (wanted '%s')", ok ? text : err.message,
          want);
    free(text);
    scene s;
    model_scene_opts o = {0};
    ok = model_scene_parse(tmp_path("moved.gltf"), &o, &s, &err);
    CHECK(ok, "model as the scene: %s", err.message);
    if (!ok) return;
    CHECK(s.instance_count == MOVED && s.model_face_count == FACES,
          "model as the scene: %d instances of %d faces", s.instance_count, s.model_face_count);
    scene_free(&s);
}

/* A mesh shared by two nodes under an emissive material is flattened (instances are not
 * lights): its faces are the scene's, and emit. A glass mesh keeps its instances but for the
 * mirrored node, whose copy is flattened (the model's faces are wound outward once). */
static void test_flattened(void) {
    char nodes[512] = "";
    node(nodes, sizeof nodes, false, 0, "");
    node(nodes, sizeof nodes, false, 1, "\"translation\":[3,0,0]");
    write_gltf("glow", 1, nodes, "0,1", "{\"emissiveFactor\":[1,0.5,0.2]}");
    scene s;
    char text[1024];
    scene_error err;
    snprintf(text, sizeof text, "%.*s mode path\nmesh file glow.gltf\n", (int)strlen(header) - 1,
             header);
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "emissive: %s", err.message);
    if (ok) {
        CHECK(s.instance_count == 0 && s.triangle_count == 2 * FACES,
              "emissive: %d instances, %d faces", s.instance_count, s.triangle_count);
        CHECK(s.triangle_count > 0 && triangle_emits(&s, &s.triangles[0]),
              "emissive: the faces do not emit");
        scene_free(&s);
    }
    node(nodes, sizeof nodes, false, 2, "\"translation\":[-3,0,0],\"scale\":[1,-1,1]");
    write_gltf("glass", 1, nodes, "0,1,2", NULL);
    if (parse_model("glass.gltf", "", &s)) { /* the file's own material: lambertian */
        CHECK(s.instance_count == 3, "glass file, own material: %d instances", s.instance_count);
        scene_free(&s);
    }
    snprintf(text, sizeof text, "%smesh refractive file glass.gltf\n", header);
    ok = parse(text, 1, &s, &err);
    CHECK(ok, "glass: %s", err.message);
    if (!ok) return;
    CHECK(s.instance_count == 2 && s.model_face_count == FACES && s.triangle_count == FACES,
          "glass: %d instances, %d model faces, %d faces", s.instance_count, s.model_face_count,
          s.triangle_count);
    film a = {0}, r = {0};
    CHECK(render_with(&s, NULL, &a) && render_with(&s, "reference", &r) && same_film(&a, &r),
          "glass: the packet build differs from the reference");
    film_free(&a), film_free(&r);
    scene_free(&s);
}

/* A node of scale zero is skipped with a warning naming it; the others stay instances. */
static void test_singular(void) {
    char nodes[512] = "";
    node(nodes, sizeof nodes, false, 0, "");
    node(nodes, sizeof nodes, false, 1, "\"translation\":[3,0,0],\"scale\":[1,0,1]");
    node(nodes, sizeof nodes, false, 2, "\"translation\":[-3,0,0]");
    write_gltf("flat_node", 1, nodes, "0,1,2", NULL);
    scene s;
    if (!parse_model("flat_node.gltf", "", &s)) return;
    CHECK(s.instance_count == 2, "singular node: %d instances", s.instance_count);
    bool warned = false;
    for (int k = 0; k < s.warning_count; k++)
        warned |= strstr(s.warnings[k].message, "'n1'") && strstr(s.warnings[k].message, "skipped");
    CHECK(warned, "singular node: no warning names node n1");
    scene_free(&s);
    nodes[0] = '\0';
    node(nodes, sizeof nodes, false, 0, "");
    node(nodes, sizeof nodes, false, 1, "\"translation\":[1e30,0,0]");
    write_gltf("far_node", 1, nodes, "0,1", NULL);
    char text[1024];
    snprintf(text, sizeof text, "%smesh file far_node.gltf\n", header);
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(!ok && err.line == 6 && strstr(err.message, "node 'n1'") &&
              strstr(err.message, "coordinate range"),
          "far node: %s %d %s", ok ? "parsed" : "refused", err.line, ok ? "" : err.message);
    if (ok) scene_free(&s);
}

/* COLLADA: three nodes instance one geometry (assimp keeps it one mesh): three instances. */
static void test_collada(void) {
    write_text("tet.dae",
               "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<COLLADA xmlns=\"http://www.collada."
               "org/2005/11/COLLADASchema\" version=\"1.4.1\"><asset><up_axis>Y_UP</up_axis>"
               "</asset><library_geometries><geometry id=\"tet\"><mesh><source id=\"p\">"
               "<float_array id=\"pa\" count=\"12\">0 0 0 1 0 0 0 1 0 0 0 1</float_array>"
               "<technique_common><accessor source=\"#pa\" count=\"4\" stride=\"3\"><param "
               "name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" "
               "type=\"float\"/></accessor></technique_common></source><vertices id=\"v\">"
               "<input semantic=\"POSITION\" source=\"#p\"/></vertices><triangles count=\"4\">"
               "<input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>0 2 1 0 1 3 0 3 2 1 2 "
               "3</p></triangles></mesh></geometry></library_geometries><library_visual_scenes>"
               "<visual_scene id=\"s\"><node id=\"a\"><instance_geometry url=\"#tet\"/></node>"
               "<node id=\"b\"><translate>2 0 0</translate><instance_geometry url=\"#tet\"/>"
               "</node><node id=\"c\"><translate>-2 0 0</translate><scale>1 2 1</scale>"
               "<instance_geometry url=\"#tet\"/></node></visual_scene></library_visual_scenes>"
               "<scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>\n");
    scene s;
    if (!parse_model("tet.dae", "", &s)) return;
    CHECK(s.instance_count == 3 && s.model_face_count == 4 && s.triangle_count == 0,
          "COLLADA: %d instances, %d model faces, %d faces", s.instance_count, s.model_face_count,
          s.triangle_count);
    film a = {0}, r = {0};
    CHECK(render_with(&s, NULL, &a) && render_with(&s, "reference", &r) && same_film(&a, &r),
          "COLLADA: the packet build differs from the reference");
    film_free(&a), film_free(&r);
    scene_free(&s);
}

/* The moved nodes (with the mesh line moved and smooth) on the CPU back end and every Vulkan
 * walk, report and path mode: the same film bit for bit. */
static void test_vulkan(void) {
    write_moved("moved", false);
    scene s;
    if (!parse_model("moved.gltf", " smooth on scale 1.2 rotate 0 1 0 20 translate 0.3 0 0", &s))
        return;
    CHECK(s.instance_count == MOVED, "vulkan: %d instances", s.instance_count);
    expect_walks_agree("moved nodes", &s);
    scene_free(&s);
}

int main(int argc, char **argv) {
    bool vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (vulkan && vk_context_device_count() == 0) {
        printf("test_mesh_nodes: no Vulkan device, skipped\n");
        return 77;
    }
    tmp_dir_make(vulkan ? "test_mesh_nodes_vulkan" : "test_mesh_nodes");
    if (vulkan) {
        test_vulkan();
        return check_summary("test_mesh_nodes vulkan");
    }
    test_identity();
    test_moved();
    test_counts();
    test_flattened();
    test_singular();
    test_collada();
    return check_summary("test_mesh_nodes");
}
