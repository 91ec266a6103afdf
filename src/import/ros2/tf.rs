//! The sonar mounts from `/tf_static`: 2-D rigid transforms, chained from a sonar's frame up
//! to the robot's.

use std::collections::BTreeMap;

/// A 2-D rigid transform (x, y, yaw).
#[derive(Clone, Copy)]
pub(super) struct Tf(pub f64, pub f64, pub f64);

/// The static transforms: each child frame's parent and its transform from the parent.
pub(super) type StaticTf = BTreeMap<String, (String, Tf)>;

fn compose(a: Tf, b: Tf) -> Tf {
    let (s, c) = a.2.sin_cos();
    Tf(a.0 + c * b.0 - s * b.1, a.1 + s * b.0 + c * b.1, a.2 + b.2)
}

/// The transform from `base` to `frame` through the chain of static transforms (at most 64
/// links), or `None` when the chain does not reach `base`.
pub(super) fn chain(static_tf: &StaticTf, base: &str, frame: &str) -> Option<Tf> {
    let mut acc: Option<Tf> = None;
    let mut current = frame;
    for _ in 0..64 {
        if current == base {
            break;
        }
        let Some((parent, tf)) = static_tf.get(current) else {
            acc = None;
            break;
        };
        acc = Some(match acc {
            Some(a) => compose(*tf, a),
            None => *tf,
        });
        current = parent;
    }
    acc.filter(|_| current == base)
}
