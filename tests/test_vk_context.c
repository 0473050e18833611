/* test_vk_context.c: the Vulkan context around the renderer: device listing and choice, the
 * validation messenger (an error must fail the run), a missing validation layer, and no driver at
 * all (the one-line error, render_vk false). Exits 77 only when no Vulkan device exists. */
#include <stdlib.h>

#include "check.h"
#include "render/render.h"
#include "test_scenes.h"
#include "render/vk/vk_context.h"

/* A one-pixel scene: one Lambertian sphere in front of the camera, one light. */
static light one_light = {
    .position = {0.0f, 0.0f, 0.0f}, .power = 10.0f, .color = {1.0f, 1.0f, 1.0f}};

static bool render_tiny(int device) {
    sphere one_sphere = ball(0.0f, 0.0f, 5.0f, 1.0f, MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    scene s = view(0.0f, 0.5f, 0.5f, 1, 2, 1, &one_sphere, 1, &one_light, 1);
    s.indirect = false;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.device = device;
    opts.validate = true;
    film f = {0};
    bool ok = render_vk(&s, &opts, &f);
    if (ok) CHECK(f.accum[3] == 2.0f, "the pixel has %g samples, want 2", f.accum[3]);
    film_free(&f);
    return ok;
}

static void test_devices(int count) {
    CHECK(vk_context_print_devices(), "listing the devices failed");
    CHECK(render_tiny(-1), "the default device failed");
    CHECK(render_tiny(0), "--device 0 failed");
    CHECK(!render_tiny(count), "--device %d (out of range) rendered", count);
    vk_context ctx;
    vk_context_desc desc = {.device = count, .validate = true};
    CHECK(!vk_context_init(&ctx, &desc), "a context on device %d (out of range)", count);
    CHECK(vk_context_destroy(&ctx), "destroying a failed context");
}

/* A command the validation layer rejects (a fill size that is no multiple of 4) must be
 * reported, counted and make the context's teardown report failure. */
static void test_validation_error(void) {
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .validate = true};
    if (!vk_context_init(&ctx, &desc)) {
        CHECK(0, "context creation failed");
        return;
    }
    CHECK(ctx.messenger != VK_NULL_HANDLE, "validation on, yet no messenger");
    vk_buffer b;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (vk_buffer_create(&ctx, 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_DEVICE, &b) &&
        vk_commands_begin(&ctx, &cmd)) {
        fprintf(stderr, "test_vk_context: a validation error is expected next\n");
        vkCmdFillBuffer(cmd, b.buffer, 0, 3, 0u);
        CHECK(VK_CHECK(vkEndCommandBuffer(cmd)), "ending the command buffer");
        CHECK(vk_context_validation_errors(&ctx) >= 1, "the bad fill was not reported");
    }
    if (cmd) vkFreeCommandBuffers(ctx.device, ctx.command_pool, 1, &cmd);
    vk_buffer_destroy(&ctx, &b);
    CHECK(!vk_context_destroy(&ctx), "teardown ignored a validation error");
}

/* The layer search path emptied: asking for validation must fail, not run unvalidated. */
static void test_missing_layer(void) {
    setenv("VK_LAYER_PATH", "/nonexistent", 1);
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .validate = true};
    CHECK(!vk_context_init(&ctx, &desc), "validation without the layer went on");
    CHECK(vk_context_destroy(&ctx), "destroying a failed context");
    unsetenv("VK_LAYER_PATH");
}

/* No driver manifest: no device, the one-line error, render_vk false. Runs last: it leaves the
 * loader without drivers. */
static void test_no_driver(void) {
    setenv("VK_ICD_FILENAMES", "/nonexistent.json", 1);
    setenv("VK_DRIVER_FILES", "/nonexistent.json", 1);
    CHECK(vk_context_device_count() == 0, "devices without a driver");
    CHECK(!vk_context_print_devices(), "listed devices without a driver");
    CHECK(!render_tiny(-1), "rendered without a driver");
}

int main(void) {
    int count = vk_context_device_count();
    if (count == 0) {
        printf("test_vk_context: no Vulkan device, skipped\n");
        return 77;
    }
    test_devices(count);
    test_validation_error();
    test_missing_layer();
    test_no_driver();
    return check_summary("test_vk_context");
}
