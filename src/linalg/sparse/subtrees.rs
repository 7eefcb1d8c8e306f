//! The elimination tree cut into whole subtrees, one thread each, and the
//! top of the tree above them.
//!
//! Column `j` of `L` is computed from the columns below it in the
//! elimination tree, its descendants, and from nothing else. So two
//! subtrees that do not contain one another can be factored at the same
//! time, by two threads, each from start to end; what is left, the
//! supernodes above all of them (the *top*), comes after them. The same
//! holds for the forward sweep of a solve, and the backward sweep runs the
//! other way: the top first, then the subtrees.
//!
//! How to cut (Geist & Ng): start from the whole tree; while the subtrees
//! cannot be shared among the threads evenly, take the heaviest, move its
//! root to the top and its children's subtrees to the list. Each subtree
//! goes to the thread with the least work so far, heaviest first (Graham's
//! "longest processing time first"). Every cut makes the subtrees easier to
//! balance and the top heavier; of the cuts tried, the one whose estimated
//! time, `(the busiest thread's work) + top_factor · (the top's work)`, is
//! least is kept. `top_factor` says how fast the caller gets through the
//! top: `1` when one thread does it, about `1 / threads` when the team
//! works on each top supernode together.
//!
//! The supernodes are numbered in a postorder of the tree, so a subtree is
//! a range of supernodes ending at its root, and a range of columns.
//!
//! Which cut is made changes how fast, never what is computed: the callers
//! form every sum in the order one thread would.
//!
//! Source: G. A. Geist and E. Ng, "Task scheduling for parallel sparse
//! Cholesky factorization", Int. J. Parallel Programming 18(4), 1989;
//! R. L. Graham, "Bounds on multiprocessing timing anomalies", SIAM J.
//! Appl. Math. 17(2), 1969.

use super::symbolic::SymbolicCholesky;
use std::ops::Range;

/// Supernodes in index order: a whole subtree given to one thread, or a
/// supernode of the top.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Item {
    /// Task `t`: the subtree [`SubtreeSchedule::task`]`(t)`.
    Task(usize),
    /// A supernode of the top.
    Top(usize),
}

/// The tree cut for a number of threads.
#[derive(Debug, Clone)]
pub struct SubtreeSchedule {
    threads: usize,
    /// Each task's supernodes, in increasing order.
    tasks: Vec<Range<usize>>,
    /// The tasks of each thread, in increasing order.
    by_thread: Vec<Vec<usize>>,
    /// Every task and top supernode, in increasing order of supernode.
    items: Vec<Item>,
}

/// How many cuts are tried per thread.
const CUTS_PER_THREAD: usize = 64;

impl SubtreeSchedule {
    /// The cut of `symbolic`'s supernodal tree for `threads` threads,
    /// with `weight[s]` the work of supernode `s` and `top_factor` as the
    /// module says.
    pub fn new(
        symbolic: &SymbolicCholesky,
        threads: usize,
        weight: &[f64],
        top_factor: f64,
    ) -> Self {
        let threads = threads.max(1);
        let tree = Tree::of(symbolic, weight);
        let roots = match tree.contiguous() {
            true => best_cut(&tree, threads, top_factor),
            false => Vec::new(), // cannot happen for a postordered tree; all top then
        };
        let mut tasks: Vec<Range<usize>> = roots.iter().map(|&r| tree.first[r]..r + 1).collect();
        tasks.sort_by_key(|t| t.start);
        let loads: Vec<f64> = tasks.iter().map(|t| tree.subtree[t.end - 1]).collect();
        let by_thread = longest_first(&loads, threads);
        let items = items(&tasks, weight.len());
        SubtreeSchedule {
            threads,
            tasks,
            by_thread,
            items,
        }
    }

    /// The number of threads it was cut for.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// The supernodes of task `t`.
    pub fn task(&self, t: usize) -> Range<usize> {
        self.tasks[t].clone()
    }

    /// The number of tasks.
    pub fn task_count(&self) -> usize {
        self.tasks.len()
    }

    /// The tasks thread `thread` runs, in increasing order.
    pub fn tasks_of(&self, thread: usize) -> &[usize] {
        &self.by_thread[thread]
    }

    /// Every task and top supernode, in increasing order of supernode:
    /// the order in which one thread would meet them.
    pub fn items(&self) -> &[Item] {
        &self.items
    }

    /// Bytes held (arrays' lengths).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.tasks.len() * (size_of::<Range<usize>>() + size_of::<usize>())
            + self.items.len() * size_of::<Item>()
    }
}

/// The supernodal tree: parents, children, each subtree's first supernode
/// and weight.
struct Tree {
    parent: Vec<Option<usize>>,
    children: Vec<Vec<usize>>,
    /// The smallest supernode in the subtree of each.
    first: Vec<usize>,
    /// The work of each subtree.
    subtree: Vec<f64>,
    own: Vec<f64>,
}

impl Tree {
    fn of(symbolic: &SymbolicCholesky, weight: &[f64]) -> Tree {
        let supernodes = symbolic.supernodes();
        let count = supernodes.len();
        assert_eq!(weight.len(), count, "one weight per supernode");
        let etree = symbolic.elimination_tree();
        let parent: Vec<Option<usize>> = (0..count)
            .map(|s| etree[supernodes.columns(s).end - 1].map(|p| supernodes.of_column(p)))
            .collect();
        let mut children = vec![Vec::new(); count];
        let (mut first, mut subtree): (Vec<usize>, Vec<f64>) =
            ((0..count).collect(), weight.to_vec());
        for s in 0..count {
            if let Some(p) = parent[s] {
                children[p].push(s);
                first[p] = first[p].min(first[s]);
                subtree[p] += subtree[s];
            }
        }
        Tree {
            parent,
            children,
            first,
            subtree,
            own: weight.to_vec(),
        }
    }

    /// Is every subtree the range of supernodes from its first to its
    /// root (a postorder), and every parent after its children?
    fn contiguous(&self) -> bool {
        let count = self.parent.len();
        let mut size = vec![1usize; count];
        for s in 0..count {
            if let Some(p) = self.parent[s] {
                if p <= s {
                    return false;
                }
                size[p] += size[s];
            }
        }
        (0..count).all(|s| s + 1 - self.first[s] == size[s])
    }

    fn roots(&self) -> Vec<usize> {
        (0..self.parent.len())
            .filter(|&s| self.parent[s].is_none())
            .collect()
    }
}

/// The roots of the subtrees of the best cut tried.
fn best_cut(tree: &Tree, threads: usize, top_factor: f64) -> Vec<usize> {
    let mut list = tree.roots();
    let mut top = 0.0;
    let estimate = |list: &[usize], top: f64| {
        let loads: Vec<f64> = list.iter().map(|&r| tree.subtree[r]).collect();
        makespan(&loads, threads) + top_factor * top
    };
    let mut best = (estimate(&list, top), list.clone());
    for _ in 0..CUTS_PER_THREAD * threads {
        let heaviest = (0..list.len()).max_by(|&a, &b| {
            let (wa, wb) = (tree.subtree[list[a]], tree.subtree[list[b]]);
            wa.total_cmp(&wb).then(list[b].cmp(&list[a]))
        });
        let Some(at) = heaviest else { break };
        let root = list[at];
        if tree.children[root].is_empty() {
            break;
        }
        list.swap_remove(at);
        list.extend(&tree.children[root]);
        top += tree.own[root];
        let time = estimate(&list, top);
        if time < best.0 {
            best = (time, list.clone());
        }
    }
    best.1
}

/// Which thread takes each task: the heaviest first, each to the thread
/// with the least work so far (ties: the lower number); each thread's
/// tasks in increasing order.
fn longest_first(loads: &[f64], threads: usize) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..loads.len()).collect();
    order.sort_by(|&a, &b| loads[b].total_cmp(&loads[a]).then(a.cmp(&b)));
    let mut work = vec![0.0f64; threads];
    let mut by_thread = vec![Vec::new(); threads];
    for t in order {
        let least = (0..threads)
            .min_by(|&a, &b| work[a].total_cmp(&work[b]).then(a.cmp(&b)))
            .expect("at least one thread");
        work[least] += loads[t];
        by_thread[least].push(t);
    }
    for tasks in &mut by_thread {
        tasks.sort_unstable();
    }
    by_thread
}

/// The busiest thread's work when `loads` are shared as [`longest_first`]
/// shares them.
fn makespan(loads: &[f64], threads: usize) -> f64 {
    let by_thread = longest_first(loads, threads);
    by_thread
        .iter()
        .map(|tasks| tasks.iter().map(|&t| loads[t]).sum::<f64>())
        .fold(0.0, f64::max)
}

/// The tasks and the supernodes between them, in increasing order.
fn items(tasks: &[Range<usize>], count: usize) -> Vec<Item> {
    let mut items = Vec::new();
    let (mut s, mut next) = (0, 0);
    while s < count {
        if next < tasks.len() && tasks[next].start == s {
            items.push(Item::Task(next));
            s = tasks[next].end;
            next += 1;
        } else {
            items.push(Item::Top(s));
            s += 1;
        }
    }
    items
}
