/* terrain_contact.c - sliding and rolling on the surface.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

void terrain_contact_run(terrain_run *r)
{
    r->res->state = RF_TRAJ_STOPPED;
    r->phase = TERRAIN_DONE;
}
