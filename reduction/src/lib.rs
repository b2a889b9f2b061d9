//! squeal-reduction: Craig–Bampton superelements, OP4 and punch DMIG.
