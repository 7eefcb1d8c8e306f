//! Pictures of sparse matrices: the pattern of `Q` (a "spy plot") and of
//! its Cholesky factor `L`, with the fill drawn apart, and the elimination
//! tree with its supernodes.
//!
//! **Spy plot.** Entry `(i, j)` of an `n × n` matrix covers the square of
//! the picture from `(j, i)·s/n` to `(j + 1, i + 1)·s/n` (`s` the picture's
//! side in pixels); when `n > s` several entries share a pixel, and the
//! pixel shows the most important of them: an entry of the matrix before
//! one of fill. Entries of `L` that are not in `P Q Pᵀ` (fill-in, created
//! by the elimination) are drawn in their own colour, so that the effect
//! of an ordering is seen at once.
//!
//! **Elimination tree.** Column `j` is a disc at `x = j` (columns in the
//! analysis's postorder, so every subtree is a contiguous range) and at a
//! height given by its depth below the root; each column is joined to its
//! parent. Columns of one supernode (a chain `j → j + 1 → …` with one shared
//! pattern) share a colour and are joined by a thick band: they are the
//! dense blocks the supernodal factorization works on.
//!
//! Cost: `O(nnz(L) + s²)` for a spy plot, `O(n + s²)` for a tree.
//! Source: the `spy` plot of MATLAB and of Davis 2006 (figures of ch. 4 and
//! 7); Liu, "The role of elimination trees in sparse factorization", SIAM
//! J. Matrix Anal. Appl. 11(1), 1990.

use super::camera::ScreenPoint;
use super::canvas::Canvas;
use super::discs::{draw_disc, DiscStyle};
use super::lines::draw_line;
use super::look::{hex, Rgb};
use super::text::{draw_text, text_height, text_width, Align};
use masssprings::mesh::procedural::RgbImage;

/// An entry of the matrix itself.
pub const ENTRY: Rgb = hex(0x1f3a5f);
/// An entry of `L` that the matrix does not have (fill-in).
pub const FILL: Rgb = hex(0xe0613a);
/// The paper.
const PAPER: Rgb = hex(0xffffff);
/// Captions.
const INK: Rgb = hex(0x1b2631);
/// The frame around a matrix.
const FRAME: Rgb = hex(0x9aa5b1);
/// Tree edges.
const EDGE: Rgb = hex(0x5d6d7e);
/// Supernode colours, in turn.
const SUPERNODE_COLOURS: [Rgb; 6] = [
    hex(0x2e86c1),
    hex(0xe67e22),
    hex(0x27ae60),
    hex(0x8e44ad),
    hex(0xc0392b),
    hex(0x16a085),
];

/// What a pixel of a spy plot shows (later variants win).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mark {
    Empty,
    Fill,
    Entry,
}

/// A square spy plot, `side` pixels, of the `n × n` pattern given column by
/// column: `mark(i, j)` for each stored `(i, j)`, with a one-pixel frame,
/// `margin` white pixels around it and the `caption` lines below.
pub fn spy(
    n: usize,
    entries: impl Iterator<Item = (usize, usize, Mark)>,
    side: usize,
    margin: usize,
    caption: &[String],
) -> RgbImage {
    let marks = rasterise(n, entries, side);
    let full = side + 2 * margin + 2;
    let scale = caption_scale(caption, full);
    let caption_height = caption.len() * (text_height(scale) + LINE_GAP * scale);
    let mut canvas = Canvas::new(full, full + caption_height);
    canvas.clear(PAPER, PAPER);
    for y in 0..side + 2 {
        for x in 0..side + 2 {
            let on_frame = x == 0 || y == 0 || x == side + 1 || y == side + 1;
            let colour = if on_frame {
                FRAME
            } else {
                match marks[(y - 1) * side + (x - 1)] {
                    Mark::Empty => continue,
                    Mark::Fill => FILL,
                    Mark::Entry => ENTRY,
                }
            };
            let i = canvas.index(margin + x, margin + y);
            canvas.colour[i] = colour;
        }
    }
    draw_caption(&mut canvas, caption, full, scale);
    canvas.downsample(1)
}

/// Which mark each of the `side × side` pixels shows.
fn rasterise(
    n: usize,
    entries: impl Iterator<Item = (usize, usize, Mark)>,
    side: usize,
) -> Vec<Mark> {
    let mut marks = vec![Mark::Empty; side * side];
    let cell = |index: usize| index * side / n.max(1);
    let cell_end = |index: usize| ((index + 1) * side).div_ceil(n.max(1)).max(cell(index) + 1);
    for (i, j, mark) in entries {
        for y in cell(i)..cell_end(i).min(side) {
            for x in cell(j)..cell_end(j).min(side) {
                let slot = &mut marks[y * side + x];
                *slot = (*slot).max(mark);
            }
        }
    }
    marks
}

/// Blank dots between caption lines.
const LINE_GAP: usize = 3;

/// Two samples per dot when every line fits the width, else one.
fn caption_scale(caption: &[String], width: usize) -> usize {
    if caption.iter().all(|line| text_width(line, 2) + 8 <= width) {
        2
    } else {
        1
    }
}

/// The caption lines, centred, from `top` down.
fn draw_caption(canvas: &mut Canvas, caption: &[String], top: usize, scale: usize) {
    let centre = (canvas.width / 2) as isize;
    for (k, line) in caption.iter().enumerate() {
        let y = top + k * (text_height(scale) + LINE_GAP * scale);
        draw_text(
            canvas,
            line,
            (centre, y as isize),
            scale,
            Align::Centre,
            INK,
        );
    }
}

/// Supersampling of the tree picture (samples per pixel along each axis).
pub const TREE_SUPERSAMPLING: usize = 3;

/// The elimination tree `parent` (postordered: `parent[j] > j`) with its
/// supernodes (`supernode_of[j]`), `width × height` pixels, the `caption`
/// lines below it.
pub fn draw_elimination_tree(
    parent: &[Option<usize>],
    supernode_of: &[usize],
    (width, height): (usize, usize),
    caption: &[String],
) -> RgbImage {
    let n = parent.len();
    let s = TREE_SUPERSAMPLING;
    let scale = caption_scale(caption, width);
    let caption_height = caption.len() * (text_height(scale) + LINE_GAP * scale);
    let mut canvas = Canvas::new(width * s, (height + caption_height) * s);
    canvas.clear(PAPER, PAPER);
    let depth = depths(parent);
    let deepest = depth.iter().copied().max().unwrap_or(0);
    let radius = node_radius(n, deepest, width, height);
    let margin = 2.0 * radius + 4.0;
    let position = |j: usize| {
        let x = margin + (width as f32 - 2.0 * margin) * (j as f32 + 0.5) / n.max(1) as f32;
        let y = margin
            + (height as f32 - 2.0 * margin) * (depth[j] as f32 + 0.5) / (deepest + 1) as f32;
        ScreenPoint {
            x: x * s as f32,
            y: y * s as f32,
            inv_depth: 1.0,
        }
    };
    let colour = |j: usize| SUPERNODE_COLOURS[supernode_of[j] % SUPERNODE_COLOURS.len()];
    for j in 0..n {
        let Some(p) = parent[j] else { continue };
        let same_supernode = supernode_of[p] == supernode_of[j];
        let (line_width, line_colour, opacity) = if same_supernode {
            ((1.4 * radius) as usize * s, colour(j), 0.55)
        } else {
            (s.max(2), EDGE, 1.0)
        };
        draw_line(
            &mut canvas,
            position(j),
            position(p),
            line_width,
            line_colour,
            opacity,
        );
    }
    for j in 0..n {
        let style = DiscStyle {
            fill: colour(j),
            radius: radius * s as f32,
            outline: Some((hex(0x1b2631), s as f32)),
        };
        draw_disc(&mut canvas, position(j), &style);
    }
    draw_caption(&mut canvas, caption, height * s, scale * s);
    canvas.downsample(s)
}

/// Depth of every node below its root (a root has depth 0), for a tree
/// whose parents come after their children.
pub fn depths(parent: &[Option<usize>]) -> Vec<usize> {
    let mut depth = vec![0; parent.len()];
    for j in (0..parent.len()).rev() {
        if let Some(p) = parent[j] {
            depth[j] = depth[p] + 1;
        }
    }
    depth
}

/// Disc radius in pixels: as large as the columns and levels allow, 2 to 9.
fn node_radius(n: usize, deepest: usize, width: usize, height: usize) -> f32 {
    let across = width as f32 / n.max(1) as f32;
    let down = height as f32 / (deepest + 1) as f32;
    (0.35 * across.min(down)).clamp(2.0, 9.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_diagonal_matrix_marks_the_diagonal_cells_only() {
        let image = spy(4, (0..4).map(|i| (i, i, Mark::Entry)), 8, 0, &[]);
        assert_eq!((image.width, image.height), (10, 10));
        let entry = ENTRY.map(|v| (v * 255.0).round() as u8);
        let paper = [255, 255, 255];
        // cell (1, 1) covers pixels 2..4 inside the frame (+1)
        assert_eq!(image.pixel(3, 3), entry);
        assert_eq!(image.pixel(4, 4), entry);
        assert_eq!(image.pixel(5, 3), paper);
        assert_eq!(image.pixel(3, 5), paper);
    }

    #[test]
    fn an_entry_wins_over_fill_in_a_shared_pixel() {
        let entries = [(0, 0, Mark::Fill), (1, 0, Mark::Entry)].into_iter();
        let image = spy(4, entries, 1, 0, &[]);
        assert_eq!(image.pixel(1, 1), ENTRY.map(|v| (v * 255.0).round() as u8));
    }

    #[test]
    fn a_caption_adds_its_lines_below_the_matrix() {
        let caption = ["n = 4".to_string(), "nnz = 4".to_string()];
        let image = spy(4, (0..4).map(|i| (i, i, Mark::Entry)), 100, 0, &caption);
        assert_eq!(image.width, 102);
        assert_eq!(image.height, 102 + 2 * (16 + 6));
        let ink = INK.map(|v| (v * 255.0).round() as u8);
        let inked = (102..image.height).any(|y| (0..image.width).any(|x| image.pixel(x, y) == ink));
        assert!(inked, "the caption is drawn");
    }

    #[test]
    fn depths_count_the_steps_to_the_root() {
        let parent = [Some(2), Some(2), Some(3), None];
        assert_eq!(depths(&parent), [2, 2, 1, 0]);
    }
}
