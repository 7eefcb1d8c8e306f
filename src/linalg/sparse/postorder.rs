//! Postorder of a forest (the elimination tree).
//!
//! A postorder numbers every node after all of its descendants, and the
//! nodes of each subtree consecutively. Renumbering the columns of `A` by a
//! postorder of its elimination tree changes neither the fill nor the tree's
//! shape, but it makes every subtree a contiguous range of columns: the
//! column counts and the supernodes rely on that.
//!
//! A depth-first search from each root, with an explicit stack instead of
//! recursion (a tree that is a path has depth `n`). Children are visited in
//! increasing order. Cost `O(n)`.
//!
//! Source: Davis 2006, §4.3 (`cs_post`, `cs_tdfs`).

/// `post[k]`: the node numbered `k` in a postorder of the forest `parent`
/// (children before parents, each subtree consecutive).
pub fn postorder(parent: &[Option<usize>]) -> Vec<usize> {
    let n = parent.len();
    let (mut next_child, next_sibling) = child_lists(parent);
    let mut post = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for root in (0..n).filter(|&j| parent[j].is_none()) {
        stack.push(root);
        while let Some(&node) = stack.last() {
            match next_child[node] {
                Some(child) => {
                    next_child[node] = next_sibling[child]; // visit each child once
                    stack.push(child);
                }
                None => {
                    stack.pop(); // all children done: number the node
                    post.push(node);
                }
            }
        }
    }
    post
}

/// Children of every node as linked lists in increasing order:
/// `(first_child, next_sibling)`.
fn child_lists(parent: &[Option<usize>]) -> (Vec<Option<usize>>, Vec<Option<usize>>) {
    let n = parent.len();
    let mut first_child = vec![None; n];
    let mut next_sibling = vec![None; n];
    // push in decreasing order so each list ends up increasing
    for j in (0..n).rev() {
        if let Some(p) = parent[j] {
            next_sibling[j] = first_child[p];
            first_child[p] = Some(j);
        }
    }
    (first_child, next_sibling)
}
