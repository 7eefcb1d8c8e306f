//! From the assembly tree to the permutation, by a postorder.
//!
//! **What it computes.** The elimination leaves an *assembly tree*: each
//! element (supernode) points to the element that absorbed it, and each
//! non-principal variable points to the supervariable or element it was
//! merged into. Any topological order of the tree (children before parents)
//! gives the same fill as the pivot order itself; a *postorder* (every
//! subtree numbered contiguously) also makes the factor's columns of a
//! subtree adjacent, which the numeric factorization likes. The steps:
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
//! **Cost.** `O(n)` time and memory.
//!
//! **Source.** SuiteSparse AMD `amd_2.c` ("compress the paths of the
//! variables", "compute output permutation"), `amd_postorder.c`,
//! `amd_post_tree.c`; Davis 2006, §4.3 (`cs_post`, `cs_tdfs`) and §7.1.

use super::quotient_graph::NONE;

/// The permutation `perm[new] = old` of the assembly tree given by
/// `parent`, `size` (> 0 for elements) and `front_size` (of elements).
/// `parent` is modified by path compression.
pub(super) fn permutation_from_assembly_tree(
    parent: &mut [i32],
    size: &[i32],
    front_size: &[i32],
) -> Vec<usize> {
    attach_variables_to_elements(parent, size);
    let (first_child, next_sibling) = children_largest_front_last(parent, size, front_size);
    let rank = postorder_elements(parent, size, first_child, &next_sibling);
    permutation_from_ranks(parent, size, &rank)
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

/// Step 2: linked lists of children (`first_child`, `next_sibling`),
/// children in increasing order except that the one with the largest front
/// is moved last.
fn children_largest_front_last(
    parent: &[i32],
    size: &[i32],
    front_size: &[i32],
) -> (Vec<i32>, Vec<i32>) {
    let n = parent.len();
    let mut first_child = vec![NONE; n];
    let mut next_sibling = vec![NONE; n];
    for j in (0..n).rev() {
        if size[j] > 0 && parent[j] != NONE {
            let p = parent[j] as usize;
            next_sibling[j] = first_child[p];
            first_child[p] = j as i32;
        }
    }
    for node in 0..n {
        if size[node] > 0 && first_child[node] != NONE {
            move_largest_child_last(node, &mut first_child, &mut next_sibling, front_size);
        }
    }
    (first_child, next_sibling)
}

/// Unlinks the child of `node` with the largest front (the last one among
/// equals) and relinks it at the end of the list.
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
/// variables. Consumes the children lists.
fn postorder_elements(
    parent: &[i32],
    size: &[i32],
    mut first_child: Vec<i32>,
    next_sibling: &[i32],
) -> Vec<i32> {
    let n = parent.len();
    let mut rank = vec![NONE; n];
    let mut stack: Vec<i32> = Vec::with_capacity(n);
    let mut next_rank = 0;
    for root in 0..n {
        if parent[root] != NONE || size[root] <= 0 {
            continue;
        }
        stack.push(root as i32);
        while let Some(&node) = stack.last() {
            let node = node as usize;
            if first_child[node] == NONE {
                // All children done: number the node.
                stack.pop();
                rank[node] = next_rank;
                next_rank += 1;
                continue;
            }
            // Push the children so that the first one is on top.
            let below = stack.len();
            let mut child = first_child[node];
            while child != NONE {
                stack.push(child);
                child = next_sibling[child as usize];
            }
            stack[below..].reverse();
            first_child[node] = NONE;
        }
    }
    rank
}

/// Step 4: positions of all variables from the element ranks.
fn permutation_from_ranks(parent: &[i32], size: &[i32], rank: &[i32]) -> Vec<usize> {
    let n = parent.len();
    let mut element_of_rank = vec![NONE; n];
    for (e, &k) in rank.iter().enumerate() {
        if k != NONE {
            element_of_rank[k as usize] = e as i32;
        }
    }
    // position[e]: first position of element e's block, then its next free slot.
    let mut position = vec![0usize; n];
    let mut next_free = 0;
    for &e in element_of_rank.iter().take_while(|&&e| e != NONE) {
        position[e as usize] = next_free;
        next_free += size[e as usize] as usize;
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
        perm[new] = old;
    }
    perm
}
