/*
 * temporary.h: the temporary files frames are written under before their rename, and removing
 * those that interrupted runs left.
 *
 * A frame is written to "<frame>.tmp-<host>-<pid>" beside it and renamed when complete
 * (image_write.c), so a run killed mid-write leaves such a file. It can be removed once the
 * process that wrote it is gone: its pid no longer exists on its host (kill(pid, 0) fails with
 * ESRCH). A temporary of another host (a render farm's nodes sharing the output folder) cannot
 * be judged from here and is left to that host's next run; one named "<frame>.tmp-<pid>" (vkrt
 * before the host was named) is judged as this host's. A live process's temporary is never
 * removed: two runs may share a folder.
 */
#ifndef VKRT_OUTPUT_TEMPORARY_H
#define VKRT_OUTPUT_TEMPORARY_H

#include <stdbool.h>
#include <stddef.h>

/* This process's temporary for target, "<target>.tmp-<host>-<pid>", into out; false when it does
 * not fit in size bytes. The host is gethostname's, with characters other than letters, digits,
 * '.' and '_' written '_'. */
bool vkrt_temporary_name(char *out, size_t size, const char *target);

/* Removes the temporaries of frames of pattern (a frame pattern, vkrt_frame_path's: "%d",
 * "%04d", "%%") whose writers are gone, beside every frame that pattern can name in its folder,
 * complete frames included. A pattern whose frame number is in a folder name removes nothing
 * (each frame's folder is swept when the frame is rendered, below). Best effort and silent;
 * returns how many files it removed. */
unsigned vkrt_temporaries_remove_dead(const char *pattern);

/* The same for the one frame at path (a path, not a pattern: '%' is a plain character). */
unsigned vkrt_temporaries_remove_dead_beside(const char *path);

#endif
