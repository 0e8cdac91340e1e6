/* SIGINT and SIGTERM during a render: the first asks the passes to stop at
 * their next launch (the image so far is then written); a second ends the
 * process at once. */
#ifndef LVCL_INTERRUPT_H
#define LVCL_INTERRUPT_H

/* Catches SIGINT and SIGTERM from here on. */
void lvcl_interrupt_catch(void);

/* The signal that asked to stop, or 0. */
int lvcl_interrupted(void);

#endif
