//! squeal-contact: gap matching and friction laws, paper eqs. (1)–(7).
