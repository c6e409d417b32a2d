//! Tracing a one-site-wide network into chains between nodes: one tracer for both graphs, the
//! crack graph (corners joined by cracks, [`crate::crack`]) and the complete graph (skeleton
//! cells joined by cell sides, [`crate::skeleton`]).
//!
//! Nodes are the sites whose number of neighbours is not two, in raster order; then every
//! chain is walked from its node, the nodes taken in order and each node's steps in the
//! lattice's neighbour order; last, every cycle that meets no node gets one at its first site
//! in raster order and is walked from there. The order of nodes and chains depends on nothing
//! else, so both graphs are deterministic.

/// A network on a lattice of sites (raster indices) whose steps join neighbouring sites.
pub(crate) trait Lattice {
    /// Number of sites.
    fn sites(&self) -> usize;
    /// Whether site `s` is on the network.
    fn member(&self, s: usize) -> bool;
    /// How many neighbours site `s` has on the network.
    fn degree(&self, s: usize) -> u8;
    /// The neighbours of site `s` on the network, in a fixed order, each with the id of the
    /// step to it: the same id from either end, below `2 * sites()`.
    fn neighbours(&self, s: usize, out: &mut Vec<(usize, usize)>);
}

/// A traced chain of sites between two nodes, before simplification.
pub(crate) struct Chain {
    /// Node index.
    pub(crate) from: usize,
    /// Node index (equal to `from` on a loop).
    pub(crate) to: usize,
    /// The sites from `from`'s to `to`'s, both ends included.
    pub(crate) sites: Vec<usize>,
    /// The steps between consecutive sites (one fewer than the sites).
    pub(crate) steps: Vec<usize>,
}

/// A network traced into nodes and chains.
pub(crate) struct Traced {
    /// The site of every node, by node index.
    pub(crate) node_sites: Vec<usize>,
    /// The node at every site (`u32::MAX` for none).
    pub(crate) node_of: Vec<u32>,
    /// Chains between nodes.
    pub(crate) chains: Vec<Chain>,
}

/// No node at a site.
pub(crate) const NO_NODE: u32 = u32::MAX;

impl Traced {
    /// Independent cycles of the traced network.
    pub(crate) fn cycle_rank(&self) -> usize {
        crate::graph::cycle_rank(
            self.node_sites.len(),
            self.chains.iter().map(|ch| (ch.from, ch.to)),
        )
    }
}

/// A network traced into nodes and chains held flat: every chain's sites and steps are
/// ranges of two shared arrays (the complete graph of a large map has millions of chains,
/// and a pair of vectors each left the allocator's heap in pieces).
pub(crate) struct FlatTraced {
    /// The site of every node, by node index.
    pub(crate) node_sites: Vec<usize>,
    /// `(from, to, first site, end of sites)` of every chain: its sites are
    /// `sites[first..end]` and its steps `steps[first - k..end - k - 1]` for the chain's
    /// index `k` (one step fewer than sites).
    pub(crate) chains: Vec<(usize, usize, usize, usize)>,
    /// The sites of all chains, chain after chain.
    pub(crate) sites: Vec<u32>,
    /// The steps of all chains, chain after chain.
    pub(crate) steps: Vec<u32>,
}

impl FlatTraced {
    /// The sites of chain `k`.
    pub(crate) fn chain_sites(&self, k: usize) -> &[u32] {
        let (_, _, a, b) = self.chains[k];
        &self.sites[a..b]
    }
}

/// Traces the network of `lattice` into nodes and chains (see the module docs).
pub(crate) fn trace<L: Lattice>(lattice: &L) -> Traced {
    let (flat, node_of) = trace_flat(lattice);
    let chains = flat
        .chains
        .iter()
        .enumerate()
        .map(|(k, &(from, to, a, b))| Chain {
            from,
            to,
            sites: flat.sites[a..b].iter().map(|&s| s as usize).collect(),
            steps: flat.steps[a - k..b - k - 1]
                .iter()
                .map(|&s| s as usize)
                .collect(),
        })
        .collect();
    Traced {
        node_sites: flat.node_sites,
        node_of,
        chains,
    }
}

/// [`trace`], flat; with the node at every site.
pub(crate) fn trace_flat<L: Lattice>(lattice: &L) -> (FlatTraced, Vec<u32>) {
    let n_sites = lattice.sites();
    let mut node_of = vec![NO_NODE; n_sites];
    let mut node_sites = Vec::new();
    // Sites of degree 2, where a cycle without nodes may be anchored.
    let mut links = Vec::new();
    for (s, node) in node_of.iter_mut().enumerate() {
        if lattice.member(s) {
            if lattice.degree(s) != 2 {
                *node = node_sites.len() as u32;
                node_sites.push(s);
            } else {
                links.push(s as u32);
            }
        }
    }
    let mut used = vec![false; 2 * n_sites];
    let mut out = FlatTraced {
        node_sites,
        chains: Vec::new(),
        sites: Vec::new(),
        steps: Vec::new(),
    };
    let mut nb = Vec::with_capacity(4);
    let mut starts = Vec::with_capacity(4);
    let mut k = 0;
    while k < out.node_sites.len() {
        let s = out.node_sites[k];
        lattice.neighbours(s, &mut starts);
        for &first in &starts {
            if !used[first.1] {
                walk(
                    lattice,
                    s,
                    first,
                    &mut used,
                    &mut node_of,
                    &mut out,
                    &mut nb,
                );
            }
        }
        k += 1;
    }
    // Cycles that meet no node: every step of a node is used by now, and a site of degree 2
    // has both its steps used or neither.
    for s in links {
        let s = s as usize;
        if node_of[s] != NO_NODE {
            continue;
        }
        lattice.neighbours(s, &mut starts);
        let first = starts[0];
        if used[first.1] {
            continue;
        }
        node_of[s] = out.node_sites.len() as u32;
        out.node_sites.push(s);
        walk(
            lattice,
            s,
            first,
            &mut used,
            &mut node_of,
            &mut out,
            &mut nb,
        );
    }
    (out, node_of)
}

/// Walks the chain leaving node site `s0` by step `first` (unused) to the next node, and
/// appends it to `out`.
fn walk<L: Lattice>(
    lattice: &L,
    s0: usize,
    first: (usize, usize),
    used: &mut [bool],
    node_of: &mut [u32],
    out: &mut FlatTraced,
    nb: &mut Vec<(usize, usize)>,
) {
    let from = node_of[s0] as usize;
    let begin = out.sites.len();
    out.sites.push(s0 as u32);
    out.steps.push(first.1 as u32);
    used[first.1] = true;
    let mut cur = first.0;
    loop {
        out.sites.push(cur as u32);
        if node_of[cur] != NO_NODE {
            break;
        }
        // Past a site of degree 2 that is not a node: the step not taken to get here.
        lattice.neighbours(cur, nb);
        let Some(&(next, step)) = nb.iter().find(|(_, k)| !used[*k]) else {
            // A chain cannot run into itself before it meets a node (a walk starts at a
            // node and a cycle without nodes gets one first); ends at a new node if it did.
            node_of[cur] = out.node_sites.len() as u32;
            out.node_sites.push(cur);
            break;
        };
        used[step] = true;
        out.steps.push(step as u32);
        cur = next;
    }
    out.chains
        .push((from, node_of[cur] as usize, begin, out.sites.len()));
}
