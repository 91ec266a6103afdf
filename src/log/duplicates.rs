//! A first pass over the JSON text that finds duplicated object keys (serde_json keeps the last
//! one silently). It allocates nothing per value but the keys of the object being read, and
//! reports the JSON path of the object that repeats a key.

use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use std::cell::RefCell;
use std::fmt;

/// One step of a JSON path.
#[derive(Clone, Copy)]
enum Step<'a> {
    Root,
    Key(&'a str),
    Index(usize),
}

/// A node of the path, linked to its parent on the stack.
#[derive(Clone, Copy)]
struct Node<'a> {
    parent: Option<&'a Node<'a>>,
    step: Step<'a>,
}

impl Node<'_> {
    fn path(&self) -> String {
        let mut steps = Vec::new();
        let mut node = Some(self);
        while let Some(n) = node {
            steps.push(n.step);
            node = n.parent;
        }
        let mut out = String::from("$");
        for step in steps.iter().rev() {
            match step {
                Step::Root => {}
                Step::Key(k) => {
                    out.push('.');
                    out.push_str(k);
                }
                Step::Index(i) => out.push_str(&format!("[{i}]")),
            }
        }
        out
    }
}

/// Where the first duplicate was found: (JSON path of the object, key).
pub(crate) type Found = RefCell<Option<(String, String)>>;

struct Check<'a> {
    node: Node<'a>,
    found: &'a Found,
}

impl<'de> DeserializeSeed<'de> for Check<'_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Check<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_none<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut index = 0;
        loop {
            let child = Check {
                node: Node {
                    parent: Some(&self.node),
                    step: Step::Index(index),
                },
                found: self.found,
            };
            if seq.next_element_seed(child)?.is_none() {
                return Ok(());
            }
            index += 1;
        }
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut keys: Vec<String> = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            if keys.contains(&key) {
                let path = self.node.path();
                let message = format!("duplicated key `{key}` in {path}");
                *self.found.borrow_mut() = Some((path, key));
                return Err(de::Error::custom(message));
            }
            let child = Check {
                node: Node {
                    parent: Some(&self.node),
                    step: Step::Key(&key),
                },
                found: self.found,
            };
            map.next_value_seed(child)?;
            keys.push(key);
        }
        Ok(())
    }
}

/// Reads `bytes` as JSON and checks that no object repeats a key.
/// On error, `found` holds the path and key when the error is a duplicate.
pub(crate) fn check_duplicates(bytes: &[u8], found: &Found) -> Result<(), serde_json::Error> {
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let seed = Check {
        node: Node {
            parent: None,
            step: Step::Root,
        },
        found,
    };
    seed.deserialize(&mut de)?;
    de.end()
}
