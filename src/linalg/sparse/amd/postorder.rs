//! From the assembly tree to the permutation, by a postorder.
//!
//! **What it computes.** The elimination leaves an *assembly tree*: each
//! element (supernode) points to the element that absorbed it, and each
//! non-principal variable points to the supervariable or element it was
//! merged into. A depth-first *postorder* of the tree (children before
//! parents, every subtree numbered contiguously) gives the same fill as the
//! pivot order itself, and keeps the columns of each subtree of the factor
//! together, which the numeric factorization likes. The steps:
//!
//! 1. **Path compression**: every non-principal variable is attached
//!    directly to the element it was eliminated with.
//! 2. **Children lists**, in increasing order of node, then the child with
//!    the largest front (`size + |Le|`; the last of equals) moved to the end
//!    of its parent's list, so it is ordered last among its siblings.
//! 3. **Depth-first postorder** from each root in increasing order, with an
//!    explicit stack (the tree can be `n` deep).
//! 4. **Permutation**: element `e` of postorder rank `k` takes the next
//!    `size[e]` positions; the variables merged into `e` come first, by
//!    increasing index, then `e` itself. Dense variables come last.
//!
//! **Cost.** `O(n)` time; the work arrays are spare `n`-vectors of the
//! quotient graph, only the permutation itself is allocated.
//!
//! **Source.** SuiteSparse AMD `amd_2.c` ("compress the paths of the
//! variables", "compute output permutation"), `amd_postorder.c`,
//! `amd_post_tree.c`; Davis 2006, §4.3 (`cs_post`, `cs_tdfs`) and §7.1.

use super::quotient_graph::AssemblyTree;
use super::NONE;

/// The permutation `perm[new] = old` of the assembly tree.
pub(super) fn permutation_from_assembly_tree(tree: AssemblyTree) -> Vec<usize> {
    let AssemblyTree {
        mut parent,
        size,
        front_size,
        workspace: [mut first_child, mut next_sibling, mut rank, mut stack],
    } = tree;
    attach_variables_to_elements(&mut parent, &size);
    link_children(&parent, &size, &mut first_child, &mut next_sibling);
    for node in 0..parent.len() {
        if size[node] > 0 && first_child[node] != NONE {
            move_largest_child_last(node, &mut first_child, &mut next_sibling, &front_size);
        }
    }
    postorder_elements(
        &parent,
        &size,
        &mut first_child,
        &next_sibling,
        &mut rank,
        &mut stack,
    );
    // The children lists are spent: reuse them for the last step.
    permutation_from_ranks(&parent, &size, &rank, &mut first_child, &mut next_sibling)
}

/// Step 1: path compression. Each non-principal, non-dense variable ends up
/// pointing to the element at the end of its chain of absorptions.
fn attach_variables_to_elements(parent: &mut [i32], size: &[i32]) {
    for i in 0..parent.len() {
        if size[i] != 0 || parent[i] == NONE {
            continue; // an element, or a dense variable
        }
        let mut element = parent[i] as usize;
        while size[element] == 0 {
            element = parent[element] as usize;
        }
        let mut j = i;
        while size[j] == 0 {
            let up = parent[j] as usize;
            parent[j] = element as i32;
            j = up;
        }
    }
}

/// Step 2a: linked lists of the children of every element, in increasing
/// order (built by pushing in decreasing order).
fn link_children(parent: &[i32], size: &[i32], first_child: &mut [i32], next_sibling: &mut [i32]) {
    first_child.fill(NONE);
    next_sibling.fill(NONE);
    for j in (0..parent.len()).rev() {
        if size[j] > 0 && parent[j] != NONE {
            let p = parent[j] as usize;
            next_sibling[j] = first_child[p];
            first_child[p] = j as i32;
        }
    }
}

/// Step 2b: unlinks the child of `node` with the largest front (the last
/// one among equals) and relinks it at the end of the list.
fn move_largest_child_last(
    node: usize,
    first_child: &mut [i32],
    next_sibling: &mut [i32],
    front_size: &[i32],
) {
    let (mut before_largest, mut largest, mut largest_front) = (NONE, NONE, -1);
    let mut previous = NONE;
    let mut child = first_child[node];
    while child != NONE {
        if front_size[child as usize] >= largest_front {
            (before_largest, largest, largest_front) =
                (previous, child, front_size[child as usize]);
        }
        previous = child;
        child = next_sibling[child as usize];
    }
    let after_largest = next_sibling[largest as usize];
    if after_largest == NONE {
        return; // already last
    }
    if before_largest == NONE {
        first_child[node] = after_largest;
    } else {
        next_sibling[before_largest as usize] = after_largest;
    }
    next_sibling[largest as usize] = NONE;
    next_sibling[previous as usize] = largest;
}

/// Step 3: `rank[e]` = position of element `e` in a depth-first postorder
/// (children in list order, roots by increasing index); [`NONE`] for
/// variables. Empties the children lists; `stack` is workspace.
fn postorder_elements(
    parent: &[i32],
    size: &[i32],
    first_child: &mut [i32],
    next_sibling: &[i32],
    rank: &mut [i32],
    stack: &mut [i32],
) {
    rank.fill(NONE);
    let mut next_rank = 0;
    for root in 0..parent.len() {
        if parent[root] != NONE || size[root] <= 0 {
            continue;
        }
        stack[0] = root as i32;
        let mut top = 1; // stack[..top] is the stack
        while top > 0 {
            let node = stack[top - 1] as usize;
            if first_child[node] == NONE {
                // All children done: number the node.
                top -= 1;
                rank[node] = next_rank;
                next_rank += 1;
                continue;
            }
            // Push the children so that the first one ends on top.
            let below = top;
            let mut child = first_child[node];
            while child != NONE {
                stack[top] = child;
                top += 1;
                child = next_sibling[child as usize];
            }
            stack[below..top].reverse();
            first_child[node] = NONE;
        }
    }
}

/// Step 4: positions of all variables from the element ranks
/// (`element_of_rank` and `position` are workspace).
fn permutation_from_ranks(
    parent: &[i32],
    size: &[i32],
    rank: &[i32],
    element_of_rank: &mut [i32],
    position: &mut [i32],
) -> Vec<usize> {
    let n = parent.len();
    element_of_rank.fill(NONE);
    for (e, &k) in rank.iter().enumerate() {
        if k != NONE {
            element_of_rank[k as usize] = e as i32;
        }
    }
    // position[e]: first position of element e's block, then its next free slot.
    let mut next_free = 0;
    for &e in element_of_rank.iter().take_while(|&&e| e != NONE) {
        position[e as usize] = next_free;
        next_free += size[e as usize];
    }
    for i in 0..n {
        if size[i] != 0 {
            continue;
        }
        if parent[i] != NONE {
            // Merged into element e: placed before e, in its block.
            let e = parent[i] as usize;
            position[i] = position[e];
            position[e] += 1;
        } else {
            // Dense: last.
            position[i] = next_free;
            next_free += 1;
        }
    }
    let mut perm = vec![0; n];
    for (old, &new) in position.iter().enumerate() {
        perm[new as usize] = old;
    }
    perm
}
