//! Vertex separator from an edge cut: the minimum vertex cover of the cut edges.

use super::graph::NodeGraph;

/// Work arrays shared by every separator computation (sized to the whole graph).
pub(crate) struct Marks {
    /// Id of the node set a node currently belongs to (`usize::MAX`: none).
    pub stamp: Vec<usize>,
    /// Side of the cut inside that set: 0 or 1.
    pub side: Vec<u8>,
    /// Scratch local index.
    pub local: Vec<usize>,
}

impl Marks {
    pub fn new(n: usize) -> Self {
        Marks {
            stamp: vec![usize::MAX; n],
            side: vec![0; n],
            local: vec![usize::MAX; n],
        }
    }
}

/// Nodes of `nodes` (all stamped `id`, split by `marks.side`) forming a minimum vertex cover of
/// the edges between side 0 and side 1: removing them disconnects the two sides. By König's
/// theorem the cover is read off a maximum matching of the bipartite cut graph; it is never
/// larger than the smaller of the two boundary layers.
pub(crate) fn min_cover_separator(
    g: &NodeGraph,
    nodes: &[usize],
    id: usize,
    marks: &mut Marks,
) -> Vec<usize> {
    let crosses = |v: usize, marks: &Marks| {
        g.neighbours(v)
            .iter()
            .any(|&u| marks.stamp[u] == id && marks.side[u] != marks.side[v])
    };
    let left: Vec<usize> = nodes
        .iter()
        .copied()
        .filter(|&v| marks.side[v] == 0 && crosses(v, marks))
        .collect();
    let right: Vec<usize> = nodes
        .iter()
        .copied()
        .filter(|&v| marks.side[v] == 1 && crosses(v, marks))
        .collect();
    if left.is_empty() {
        return Vec::new();
    }
    for (k, &v) in right.iter().enumerate() {
        marks.local[v] = k;
    }
    let mut ptr = Vec::with_capacity(left.len() + 1);
    ptr.push(0);
    let mut adj = Vec::new();
    for &v in &left {
        for &u in g.neighbours(v) {
            if marks.stamp[u] == id && marks.side[u] == 1 {
                adj.push(marks.local[u]);
            }
        }
        ptr.push(adj.len());
    }
    for &v in &right {
        marks.local[v] = usize::MAX;
    }
    let (match_l, match_r) = hopcroft_karp(left.len(), right.len(), &ptr, &adj);

    // König: Z = vertices reachable from free left vertices by alternating paths;
    // cover = (left \ Z) ∪ (right ∩ Z).
    let mut zl = vec![false; left.len()];
    let mut zr = vec![false; right.len()];
    let mut queue: Vec<usize> = (0..left.len()).filter(|&l| match_l[l] == NONE).collect();
    for &l in &queue {
        zl[l] = true;
    }
    while let Some(l) = queue.pop() {
        for &r in &adj[ptr[l]..ptr[l + 1]] {
            if !zr[r] {
                zr[r] = true;
                let l2 = match_r[r];
                if l2 != NONE && !zl[l2] {
                    zl[l2] = true;
                    queue.push(l2);
                }
            }
        }
    }
    let mut sep: Vec<usize> = left
        .iter()
        .zip(&zl)
        .filter(|(_, &z)| !z)
        .map(|(&v, _)| v)
        .collect();
    sep.extend(right.iter().zip(&zr).filter(|(_, &z)| z).map(|(&v, _)| v));
    sep
}

const NONE: usize = usize::MAX;

/// Maximum matching of a bipartite graph (left vertices 0..nl with neighbour lists
/// `adj[ptr[l]..ptr[l+1]]` among right vertices 0..nr). Returns (match of left, match of right),
/// `NONE` when unmatched.
fn hopcroft_karp(nl: usize, nr: usize, ptr: &[usize], adj: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut ml = vec![NONE; nl];
    let mut mr = vec![NONE; nr];
    // Greedy start.
    for l in 0..nl {
        if let Some(&r) = adj[ptr[l]..ptr[l + 1]].iter().find(|&&r| mr[r] == NONE) {
            ml[l] = r;
            mr[r] = l;
        }
    }
    let mut dist = vec![0usize; nl];
    let mut next = vec![0usize; nl];
    loop {
        // BFS layers from the free left vertices.
        let mut queue: Vec<usize> = Vec::with_capacity(nl);
        for l in 0..nl {
            if ml[l] == NONE {
                dist[l] = 0;
                queue.push(l);
            } else {
                dist[l] = NONE;
            }
        }
        let mut found = false;
        let mut head = 0;
        while head < queue.len() {
            let l = queue[head];
            head += 1;
            for &r in &adj[ptr[l]..ptr[l + 1]] {
                let l2 = mr[r];
                if l2 == NONE {
                    found = true;
                } else if dist[l2] == NONE {
                    dist[l2] = dist[l] + 1;
                    queue.push(l2);
                }
            }
        }
        if !found {
            return (ml, mr);
        }
        // Vertex-disjoint shortest augmenting paths by iterative DFS along the layers.
        next.copy_from_slice(&ptr[..nl]);
        for root in 0..nl {
            if ml[root] != NONE {
                continue;
            }
            let mut path = vec![root];
            while let Some(&l) = path.last() {
                if next[l] == ptr[l + 1] {
                    dist[l] = NONE; // dead end
                    path.pop();
                    continue;
                }
                let r = adj[next[l]];
                next[l] += 1;
                let l2 = mr[r];
                if l2 == NONE {
                    // Augment along the path: each left vertex takes the right vertex it was
                    // exploring (next[l] - 1).
                    for &pl in path.iter().rev() {
                        let pr = adj[next[pl] - 1];
                        mr[pr] = pl;
                        ml[pl] = pr;
                    }
                    break;
                } else if dist[l2] != NONE && dist[l2] == dist[l] + 1 {
                    path.push(l2);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matching_is_maximum_on_a_small_graph() {
        // Left 0..3, right 0..3; a perfect matching exists (0-1, 1-0, 2-2) but greedy takes 0-0.
        let ptr = [0, 2, 3, 5];
        let adj = [0, 1, 0, 0, 2];
        let (ml, mr) = hopcroft_karp(3, 3, &ptr, &adj);
        assert!(ml.iter().all(|&r| r != NONE), "{ml:?}");
        for (l, &r) in ml.iter().enumerate() {
            assert_eq!(mr[r], l);
            assert!(adj[ptr[l]..ptr[l + 1]].contains(&r));
        }
    }
}
