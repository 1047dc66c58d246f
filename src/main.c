/*
 * main.c: the vkrt program. Parses the command line (cmd/cli.h) and hands it to its command's
 * module: cmd/render.h, cmd/view.h, cmd/bench.h. Only main and those commands decide how the
 * process exits.
 */
#include <stdio.h>

#include "clock.h"
#include "cmd/bench.h"
#include "cmd/cli.h"
#include "cmd/render.h"
#include "cmd/view.h"
#include "error.h"
#include "gpu/context.h"
#include "gpu/spirv_cache.h"

#ifndef VKRT_VERSION
#define VKRT_VERSION "unknown"
#endif

int main(int argc, char **argv)
{
    double main_ms = vkrt_clock_ms();
    vkrt_command_line cl;
    vkrt_error err = {{0}};
    if (!vkrt_command_line_parse(argc, argv, &cl, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 2;
    }
    const vkrt_common_options *common = cl.command == VKRT_COMMAND_RENDER ? &cl.render.common
                                        : cl.command == VKRT_COMMAND_VIEW ? &cl.view.common
                                        : cl.command == VKRT_COMMAND_BENCH ? &cl.bench.common
                                                                           : NULL;
    if (common && common->no_cache)
        gpu_spirv_cache_disable();
    switch (cl.command) {
    case VKRT_COMMAND_HELP:
        fputs(vkrt_usage(), stdout);
        return 0;
    case VKRT_COMMAND_VERSION:
        printf("vkrt %s\n", VKRT_VERSION);
        return 0;
    case VKRT_COMMAND_LIST_DEVICES:
        if (!gpu_list_devices(stdout, &err)) {
            fprintf(stderr, "vkrt: %s\n", err.msg);
            return 1;
        }
        return 0;
    case VKRT_COMMAND_RENDER:
        return vkrt_cmd_render(&cl, main_ms);
    case VKRT_COMMAND_VIEW:
        return vkrt_cmd_view(&cl);
    case VKRT_COMMAND_BENCH:
        return vkrt_cmd_bench(&cl);
    default:
        return 2;
    }
}
