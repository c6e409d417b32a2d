//! Union-find over node or cell indices, shared by the field, the regions and the graph.

/// Union-find: the root of `i` in the forest `parent`, halving the path on the way.
pub(crate) fn find_root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}
