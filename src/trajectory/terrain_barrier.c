/* terrain_barrier.c - barrier crossings of a piece of path.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

terrain_piece_outcome terrain_barrier_piece(terrain_run *r, const terrain_piece *pc, double *tau_cut, double *scale)
{
    (void)r, (void)pc;
    *tau_cut = INFINITY, *scale = 1;
    return TERRAIN_PIECE_FREE;
}
