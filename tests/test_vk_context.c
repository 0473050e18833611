/* test_vk_context.c: the Vulkan context around the renderer: device listing and choice, the
 * validation messenger (an error must fail the run), a missing or unloadable validation layer,
 * lavapipe's thread count, a file-size limit (a render under `ulimit -f 16` ends, never by a
 * signal: lavapipe of Mesa 25 keeps device memory in a memfd the limit caps), no driver at all
 * (the one-line error, render_film false), and, run as `test_vk_context no-loader`, no loader at
 * all. Exits 77 only when no Vulkan device exists. */
#include <dirent.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"
#include "tmp_dir.h"
#include "util/log.h"

/* A one-pixel scene: one Lambertian sphere in front of the camera, one light. */
static light one_light = {
    .position = {0.0f, 0.0f, 0.0f}, .power = 10.0f, .color = {1.0f, 1.0f, 1.0f}};

static bool render_tiny(int device) {
    sphere one_sphere = ball(0.0f, 0.0f, 5.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    scene s = view(0.0f, 0.5f, 0.5f, 1, 2, 1, &one_sphere, 1, &one_light, 1);
    s.indirect = false;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.device = device;
    opts.device_given = device >= 0;
    opts.validate = true;
    film f = {0};
    bool ok = render_film(&render_backend_vulkan, &s, &opts, &f);
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

/* A layer manifest whose library does not exist (a half-removed package): the error must say
 * that the layer could not be loaded, and why. */
static void test_unloadable_layer(void) {
    const char *missing = "/nonexistent/libVkLayer_khronos_validation.so";
    FILE *manifest = fopen(tmp_path("VkLayer_khronos_validation.json"), "w");
    if (!manifest) {
        CHECK(0, "cannot write the layer manifest");
        return;
    }
    fprintf(manifest,
            "{\"file_format_version\": \"1.2.0\", \"layer\": {\"name\": "
            "\"VK_LAYER_KHRONOS_validation\", \"type\": \"GLOBAL\", \"library_path\": \"%s\", "
            "\"api_version\": \"1.3.0\", \"implementation_version\": \"1\", "
            "\"description\": \"a manifest whose library is gone\"}}\n",
            missing);
    fclose(manifest);
    setenv("VK_LAYER_PATH", tmpdir, 1);
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .validate = true};
    log_hold_errors();
    CHECK(!vk_context_init(&ctx, &desc), "validation with an unloadable layer went on");
    const char *errors = log_release_errors();
    CHECK(strstr(errors, "VK_LAYER_KHRONOS_validation could not be loaded") != NULL,
          "the error does not say the layer could not be loaded: \"%s\"", errors);
    CHECK(strstr(errors, missing) != NULL, "the error does not say why: \"%s\"", errors);
    CHECK(vk_context_destroy(&ctx), "destroying a failed context");
    unsetenv("VK_LAYER_PATH");
    remove(tmp_path("VkLayer_khronos_validation.json"));
}

/* Threads of this process while a context on `threads` lavapipe workers is open. */
static int threads_with(int threads) {
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .threads = threads};
    if (!vk_context_init(&ctx, &desc)) return -1;
    int count = 0;
    DIR *tasks = opendir("/proc/self/task");
    for (struct dirent *e; tasks && (e = readdir(tasks));) count += e->d_name[0] != '.';
    if (tasks) closedir(tasks);
    vk_context_destroy(&ctx);
    return count;
}

/* --threads reaches lavapipe: more workers, more threads in the process; the user's own
 * LP_NUM_THREADS is used when no count is given and left as it was. */
static void test_threads(void) {
    vk_context ctx;
    vk_context_desc desc = {.device = -1};
    if (!vk_context_init(&ctx, &desc)) {
        CHECK(0, "context creation failed");
        return;
    }
    bool lavapipe = vk_context_is_lavapipe(&ctx);
    vk_context_destroy(&ctx);
    if (!lavapipe) return;
    int one = threads_with(1), six = threads_with(6);
    CHECK(one > 0 && six > one, "1 worker: %d threads, 6 workers: %d threads", one, six);
    CHECK(getenv("LP_NUM_THREADS") == NULL, "LP_NUM_THREADS left set");
    setenv("LP_NUM_THREADS", "6", 1);
    int user = threads_with(0);
    CHECK(user == six, "LP_NUM_THREADS=6 gave %d threads, --threads 6 %d", user, six);
    CHECK(threads_with(1) == one, "--threads 1 under LP_NUM_THREADS=6");
    const char *kept = getenv("LP_NUM_THREADS");
    CHECK(kept && !strcmp(kept, "6"), "LP_NUM_THREADS is %s, was 6", kept ? kept : "unset");
    unsetenv("LP_NUM_THREADS");
}

/* No loader (TRAZADOR_VK_LOADER names one that does not exist): the error names the library
 * that could not be opened and points nowhere else. Run in a process of its own, since the
 * loader is opened once. */
static int test_no_loader(void) {
    setenv("TRAZADOR_VK_LOADER", "/nonexistent/libvulkan.so.1", 1);
    CHECK(vk_context_device_count() == 0, "devices without a loader");
    log_hold_errors();
    CHECK(!render_tiny(-1), "rendered without a loader");
    const char *errors = log_release_errors();
    CHECK(strstr(errors, "cannot open the Vulkan loader /nonexistent/libvulkan.so.1") != NULL,
          "the error does not name the loader: \"%s\"", errors);
    CHECK(strstr(errors, "VK_LOADER_DEBUG") == NULL, "the error suggests VK_LOADER_DEBUG: \"%s\"",
          errors);
    return check_summary("test_vk_context no-loader");
}

/* `test_vk_context file-limit`, run by test_file_limit under the limit: 0 when the tiny render
 * worked, 3 when it was refused for the memfd, 4 when it failed otherwise. */
static int file_limit_child(void) {
    log_hold_errors();
    bool ok = render_tiny(-1);
    const char *errors = log_release_errors();
    if (ok) return 0;
    fprintf(stderr, "test_vk_context file-limit: %s\n", errors);
    return strstr(errors, "memfd") ? 3 : 4;
}

/* A file-size limit of 16 KiB (SIGXFSZ ignored, as a shell script standing for a full disk
 * does): the render either works (Mesa 22.3, whose memory is no file) or is refused with the
 * memfd message (Mesa 25); it must not die of SIGBUS. */
static void test_file_limit(void) {
    fflush(NULL);
    pid_t child = fork();
    if (child == 0) {
        struct rlimit limit = {16384, 16384};
        signal(SIGXFSZ, SIG_IGN);
        if (setrlimit(RLIMIT_FSIZE, &limit) == 0)
            execl("/proc/self/exe", "test_vk_context", "file-limit", (char *)NULL);
        _exit(5);
    }
    int status = 0;
    CHECK(child > 0 && waitpid(child, &status, 0) == child, "fork or wait failed");
    CHECK(WIFEXITED(status), "under ulimit -f 16 the render died of signal %d",
          WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    CHECK(code == 0 || code == 3, "under ulimit -f 16 the child exited %d", code);
    printf("test_vk_context: under ulimit -f 16 the render %s\n",
           code == 0   ? "worked"
           : code == 3 ? "was refused (lavapipe's memfd)"
                       : "failed");
}

/* No driver manifest: no device, the one-line error, render_film false. Runs last: it leaves the
 * loader without drivers. */
static void test_no_driver(void) {
    setenv("VK_ICD_FILENAMES", "/nonexistent.json", 1);
    setenv("VK_DRIVER_FILES", "/nonexistent.json", 1);
    CHECK(vk_context_device_count() == 0, "devices without a driver");
    CHECK(!vk_context_print_devices(), "listed devices without a driver");
    CHECK(!render_tiny(-1), "rendered without a driver");
}

int main(int argc, char **argv) {
    if (argc > 1 && !strcmp(argv[1], "no-loader")) return test_no_loader();
    if (argc > 1 && !strcmp(argv[1], "file-limit")) return file_limit_child();
    if (!tmp_dir_make("test_vk_context")) {
        perror("test_vk_context: mkdtemp");
        return 1;
    }
    int count = vk_context_device_count();
    if (count == 0) {
        printf("test_vk_context: no Vulkan device, skipped\n");
        return 77;
    }
    test_devices(count);
    test_validation_error();
    test_missing_layer();
    test_unloadable_layer();
    test_threads();
    test_file_limit();
    test_no_driver();
    rmdir(tmpdir);
    return check_summary("test_vk_context");
}
