/* SIGINT, SIGTERM and SIGUSR2 during a render: the first asks the passes
 * to stop at their next launch (the image so far is then written); a second
 * ends the process at once. SIGUSR2 is for lvcl-mpi: mpirun forwards it to
 * every rank, where it ends the whole job on the other two. */
#ifndef LVCL_INTERRUPT_H
#define LVCL_INTERRUPT_H

/* Catches SIGINT, SIGTERM and SIGUSR2 from here on. */
void lvcl_interrupt_catch(void);

/* The signal that asked to stop, or 0. */
int lvcl_interrupted(void);

#endif
