/* mpi_internal.h - what the runner asks of mpi.c: rank 0 serves the worker
 * ranks from the batch's queue. */
#ifndef ROCKFUZZ_MPI_INTERNAL_H
#define ROCKFUZZ_MPI_INTERNAL_H

#include "study/batch.h"

/* Serve the worker ranks until the queue is empty and every local worker has
 * returned; draws the progress line while it waits. */
void rf_mpi_serve_batch(rf_batch *b);

#endif
