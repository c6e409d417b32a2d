//! Pruning a graph: dead-end spurs shorter than a length ([`VoronoiGraph::prune_spurs`]),
//! dead ends leaf first under any rule ([`VoronoiGraph::prune_dead_ends`]: the complete
//! graph's wall wiggles, and whatever leads to neither start nor goal), and the renumbering of
//! the nodes that remain. Start and goal are never removed.

use homospline_geom::Real;

use crate::graph::{NodeKind, VoronoiGraph};

impl VoronoiGraph {
    /// Removes dead-end spurs shorter than `min_length` (map units), repeatedly (all the short
    /// spurs of a round at once), then drops the nodes this leaves without edges (degree-2
    /// nodes stay). Start and goal are never removed.
    pub fn prune_spurs(&mut self, min_length: Real) {
        loop {
            let mut degree = vec![0usize; self.nodes.len()];
            for e in &self.edges {
                degree[e.from] += 1;
                degree[e.to] += 1;
            }
            let removable = |n: usize| {
                degree[n] == 1 && !matches!(self.nodes[n].kind, NodeKind::Start | NodeKind::Goal)
            };
            let before = self.edges.len();
            self.edges.retain(|e| {
                !(e.length < min_length && e.from != e.to && (removable(e.from) || removable(e.to)))
            });
            if self.edges.len() == before {
                break;
            }
        }
        self.compact();
    }

    /// Drops nodes no edge uses and renumbers.
    fn compact(&mut self) {
        let mut used = vec![false; self.nodes.len()];
        for e in &self.edges {
            used[e.from] = true;
            used[e.to] = true;
        }
        self.keep_nodes(used);
    }

    /// Keeps the nodes marked in `keep` (and start and goal) and renumbers; every edge's ends
    /// must be kept.
    fn keep_nodes(&mut self, mut keep: Vec<bool>) {
        for n in [self.start, self.goal].into_iter().flatten() {
            keep[n] = true;
        }
        // Compacted in place, in order (a second array of nodes was as large as the graph's
        // nodes on a map's query graph); `map` takes each kept node to its new index.
        let mut map = vec![usize::MAX; self.nodes.len()];
        let (mut old, mut new) = (0, 0);
        self.nodes.retain_mut(|node| {
            let kept = keep[old];
            if kept {
                map[old] = new;
                node.id = new;
                new += 1;
            }
            old += 1;
            kept
        });
        self.nodes.shrink_to_fit();
        for e in &mut self.edges {
            e.from = map[e.from];
            e.to = map[e.to];
        }
        self.start = self.start.map(|s| map[s]);
        self.goal = self.goal.map(|s| map[s]);
    }

    /// Removes dead ends, leaf first, while `removable(graph, edge, leaf node)` says so. Start
    /// and goal are never removed, nor the last edge of a component (both of its ends
    /// leaves), so every piece of the graph keeps at least one edge. Drops the nodes this
    /// leaves without edges (nodes that had none to begin with stay).
    pub fn prune_dead_ends(&mut self, removable: impl Fn(&VoronoiGraph, usize, usize) -> bool) {
        let n = self.nodes.len();
        let mut degree = vec![0usize; n];
        for e in &self.edges {
            degree[e.from] += 1;
            degree[e.to] += 1;
        }
        let adjacency = self.adjacency(|_| true);
        let incident = |k: usize| adjacency.of(k).map(|l| l.1);
        let had_edges: Vec<bool> = degree.iter().map(|&d| d > 0).collect();
        let protected = |k: usize, g: &VoronoiGraph| {
            matches!(g.nodes[k].kind, NodeKind::Start | NodeKind::Goal)
        };
        let mut alive = vec![true; self.edges.len()];
        let mut queue: Vec<usize> = (0..n)
            .filter(|&k| degree[k] == 1 && !protected(k, self))
            .rev()
            .collect();
        while let Some(leaf) = queue.pop() {
            if degree[leaf] != 1 {
                continue;
            }
            let Some(e) = incident(leaf).find(|&e| alive[e]) else {
                continue;
            };
            let edge = &self.edges[e];
            let other = if edge.from == leaf {
                edge.to
            } else {
                edge.from
            };
            if degree[other] == 1 || !removable(self, e, leaf) {
                continue;
            }
            alive[e] = false;
            degree[leaf] = 0;
            degree[other] -= 1;
            if degree[other] == 1 && !protected(other, self) {
                queue.push(other);
            }
        }
        let keep_node: Vec<bool> = (0..n).map(|k| degree[k] > 0 || !had_edges[k]).collect();
        let mut k = 0;
        self.edges.retain(|_| {
            k += 1;
            alive[k - 1]
        });
        self.edges.shrink_to_fit();
        self.keep_nodes(keep_node);
    }
}
