//! Grid brushfire distance field and the hierarchical generalized Voronoi graph (filled by the voronoi issue).
