//! Faces turned away that only openings can show.
//!
//! A mesh with [`Mesh::openings`](crate::scene::Mesh::openings) bounds solids:
//! every edge but the openings' is shared by two triangles that run it in
//! opposite directions, and the faces are turned outwards. Close each opening
//! with a fan of triangles from its first vertex, running the opening's edges
//! the other way round: the surface is then closed and turned outwards, and
//! every point has a winding number, how many of the solids hold it (zero
//! outside, never negative). A ray from a viewer outside the solids (winding
//! number zero) that reaches a face turned away reaches it from inside (one
//! or more), so on the way it has entered a solid through a triangle turned
//! towards the viewer (a triangle turned away is where a ray leaves): one of
//! the mesh's, nearer, which hides the face there, or a fan's triangle that
//! faces the viewer. An opening's box on screen is the box of those of its
//! fan's triangles, so a face turned away whose box meets no opening's box is
//! hidden at every sample inside it, and is not drawn. An opening whose whole
//! fan faces away has no box: the teapot's lid, seen from above, closes over
//! its rim with a fan that faces down.
//!
//! The argument leaves out a sample on the face's very edge, where the ray
//! only grazes the solid: there the face can tie in depth with the face
//! beside it, and skipping it gives the sample to that face or to what lies
//! behind, as culling the faces turned away of a closed mesh does.
//!
//! The viewer is outside the solids when every vertex of the mesh lies before
//! the near plane: the solids lie within the vertices' convex hull. A frame in
//! which a vertex does not, or in which a vertex of an opening lies outside the
//! guard band, draws every face of the object.

use crate::fixed_point::SUBPIXEL_BITS;
use crate::renderer::ScreenVertex;
use crate::scene::OPENING_END;
use crate::setup::{is_backfacing, signed_area2, SetupVertex};

/// Opening boxes kept per object; the openings past the last widen its box.
const MAX_OPENING_BOXES: usize = 8;

/// The screen boxes (pixels, first and last column and row) of an object's
/// openings in the current frame: each the box of the triangles of the
/// opening's fan that face the viewer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpeningBoxes {
    /// 0 when every face turned away is drawn, else one more than the boxes
    /// in use (so the value of all-zero workspace memory draws every face,
    /// and the statics that hold it stay out of `.data`).
    boxes_and_one: u8,
    boxes: [[i16; 4]; MAX_OPENING_BOXES],
}

impl OpeningBoxes {
    /// An object whose faces turned away are all drawn (all zero).
    pub const DRAW_ALL: Self = Self {
        boxes_and_one: 0,
        boxes: [[0; 4]; MAX_OPENING_BOXES],
    };

    /// The boxes of the openings `openings` (vertex indices into `vertices`,
    /// each loop ended by [`OPENING_END`]) of an object whose vertices are
    /// `vertices`, all before the near plane when `before_near` holds.
    pub fn of(openings: &[u32], vertices: &[ScreenVertex], before_near: bool) -> Self {
        if !before_near {
            return Self::DRAW_ALL;
        }
        let mut boxes = [[0i16; 4]; MAX_OPENING_BOXES];
        let mut count = 0usize;
        // The current loop's first vertex and the last one seen (from its
        // second vertex on), and whether a triangle of the fan that closes
        // it has faced the viewer yet.
        let mut first: Option<SetupVertex> = None;
        let mut previous: Option<SetupVertex> = None;
        let mut open = false;
        for &v in openings {
            if v == OPENING_END {
                if open && count < MAX_OPENING_BOXES {
                    count += 1;
                }
                (first, previous, open) = (None, None, false);
                continue;
            }
            let Some(p) = vertices.get(v as usize) else {
                return Self::DRAW_ALL;
            };
            if p.outcode() != 0 {
                return Self::DRAW_ALL;
            }
            let here = SetupVertex {
                x: p.x(),
                y: p.y(),
                z: 0,
            };
            match (first, previous) {
                (None, _) => first = Some(here),
                (Some(_), None) => previous = Some(here),
                (Some(start), Some(last)) => {
                    // The fan runs the loop's edges the other way round; a
                    // triangle seen edge-on counts as facing the viewer.
                    let fan = [start, here, last];
                    if !is_backfacing(signed_area2(&fan)) {
                        let b = &mut boxes[count.min(MAX_OPENING_BOXES - 1)];
                        for corner in fan {
                            // Within the guard band a pixel coordinate fits `i16`.
                            let (x, y) = (
                                (corner.x >> SUBPIXEL_BITS) as i16,
                                (corner.y >> SUBPIXEL_BITS) as i16,
                            );
                            if open || count == MAX_OPENING_BOXES {
                                *b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
                            } else {
                                *b = [x, x, y, y];
                            }
                            open = true;
                        }
                    }
                    previous = Some(here);
                }
            }
        }
        if open && count < MAX_OPENING_BOXES {
            count += 1;
        }
        Self {
            boxes_and_one: count as u8 + 1,
            boxes,
        }
    }

    /// Whether a face turned away whose pixels lie within columns
    /// `min_x..=max_x` and rows `min_y..=max_y` is hidden: its box meets no
    /// opening's (but for samples on its very edge: see the module
    /// documentation).
    #[inline]
    pub fn hide_face(&self, min_x: i32, max_x: i32, min_y: i32, max_y: i32) -> bool {
        let Some(count) = (self.boxes_and_one as usize).checked_sub(1) else {
            return false;
        };
        !self.boxes[..count].iter().any(|b| {
            min_x <= b[1] as i32
                && b[0] as i32 <= max_x
                && min_y <= b[3] as i32
                && b[2] as i32 <= max_y
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex at pixel `(x, y)` (its corner), with `outcode`.
    fn at(x: i32, y: i32, outcode: u8) -> ScreenVertex {
        ScreenVertex::new(x << SUBPIXEL_BITS, y << SUBPIXEL_BITS, 0, [0; 3], outcode)
    }

    #[test]
    fn faces_beside_every_opening_are_hidden() {
        let vertices =
            [(10, 10), (20, 12), (15, 30), (48, 45), (52, 45), (50, 50)].map(|(x, y)| at(x, y, 0));
        let list = [0, 1, 2, OPENING_END, 3, 4, 5, OPENING_END];
        let boxes = OpeningBoxes::of(&list, &vertices, true);
        // The first opening covers columns 10..=20, rows 10..=30.
        assert!(!boxes.hide_face(0, 10, 0, 10));
        assert!(!boxes.hide_face(18, 25, 29, 40));
        assert!(boxes.hide_face(21, 40, 0, 40));
        assert!(boxes.hide_face(0, 40, 31, 49));
        // The second covers columns 48..=52, rows 45..=50.
        assert!(!boxes.hide_face(50, 60, 45, 50));
        assert!(boxes.hide_face(53, 60, 45, 50));
        // A closed mesh: every face turned away is hidden.
        assert!(OpeningBoxes::of(&[], &vertices, true).hide_face(0, 100, 0, 100));
    }

    #[test]
    fn only_the_fan_triangles_that_face_the_viewer_make_a_box() {
        // A square loop: run one way, its fan faces the viewer (clockwise in
        // window coordinates, y down); run the other way, it faces away and
        // has no box.
        let square = [(10, 10), (30, 10), (30, 30), (10, 30)].map(|(x, y)| at(x, y, 0));
        let facing = OpeningBoxes::of(&[0, 1, 2, 3, OPENING_END], &square, true);
        assert!(!facing.hide_face(20, 20, 20, 20));
        let away = OpeningBoxes::of(&[0, 3, 2, 1, OPENING_END], &square, true);
        assert!(away.hide_face(20, 20, 20, 20));
        assert!(away.hide_face(0, 100, 0, 100));
        // Of the fan (0 2 1), (0 3 2), (0 4 3) only the first faces the
        // viewer: the box is columns 10..=30, not 10..=50.
        let bent = [(10, 10), (30, 10), (30, 30), (50, 30), (50, 10)].map(|(x, y)| at(x, y, 0));
        let boxes = OpeningBoxes::of(&[0, 1, 2, 3, 4, OPENING_END], &bent, true);
        assert!(!boxes.hide_face(25, 28, 12, 28));
        assert!(!boxes.hide_face(30, 45, 12, 28));
        assert!(boxes.hide_face(31, 45, 12, 28));
    }

    #[test]
    fn openings_past_the_last_box_widen_it() {
        // Ten small openings facing the viewer, columns 10 k ..= 10 k + 2.
        let vertices: [ScreenVertex; 30] = core::array::from_fn(|v| {
            let k = v as i32 / 3;
            [at(10 * k, 0, 0), at(10 * k + 2, 0, 0), at(10 * k + 1, 2, 0)][v % 3]
        });
        let list: [u32; 40] = core::array::from_fn(|i| {
            if i % 4 == 3 {
                OPENING_END
            } else {
                (i / 4 * 3 + i % 4) as u32
            }
        });
        let boxes = OpeningBoxes::of(&list, &vertices, true);
        for k in 0..10 {
            assert!(!boxes.hide_face(10 * k, 10 * k, 0, 0), "{k}");
        }
        // Between two openings the last box spans 70..=92.
        assert!(boxes.hide_face(63, 69, 0, 0));
        assert!(!boxes.hide_face(75, 85, 0, 0));
    }

    #[test]
    fn a_vertex_outside_or_behind_draws_every_face() {
        let inside = [at(10, 10, 0), at(20, 12, 0), at(15, 30, 0)];
        let list = [0, 1, 2, OPENING_END];
        assert_eq!(
            OpeningBoxes::of(&list, &inside, false),
            OpeningBoxes::DRAW_ALL
        );
        let outside = [at(10, 10, 0), at(20, 12, 1), at(15, 30, 0)];
        assert_eq!(
            OpeningBoxes::of(&list, &outside, true),
            OpeningBoxes::DRAW_ALL
        );
        assert_eq!(
            OpeningBoxes::of(&[5, OPENING_END], &inside, true),
            OpeningBoxes::DRAW_ALL
        );
        assert!(!OpeningBoxes::DRAW_ALL.hide_face(1000, 1000, 1000, 1000));
    }
}
