//! squeal-fe: solid elements, materials, sparse assembly, modal solve.
