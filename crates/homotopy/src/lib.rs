//! Homotopy signatures and the k best homotopy-distinct paths (filled by the homotopy issue).
