//! ROS 2 recordings for the importer tests, built byte by byte (CDR messages, MCAP files), and
//! the check that an import is refused with its place.

use sonarmap::import::{builtin_layout, ImportError, ImportOptions, Imported};
use sonarmap::units::Units;
use std::collections::BTreeMap;
use std::io::Cursor;

/// Expects an error whose message contains every part.
pub(crate) fn check_err(result: Result<Imported, ImportError>, parts: &[&str]) {
    let e = match result {
        Ok(i) => panic!(
            "expected an error with {parts:?}, got {} snapshots",
            i.run.snapshots.len()
        ),
        Err(e) => e.to_string(),
    };
    for p in parts {
        assert!(e.contains(p), "error lacks {p:?}: {e}");
    }
}

pub(crate) fn nomad_options() -> ImportOptions {
    ImportOptions {
        layout: builtin_layout("nomad_200"),
        units: Some(Units::Inches),
        ..ImportOptions::default()
    }
}

/// A CDR writer for the test messages (little or big endian).
pub(crate) struct Cdr {
    pub(crate) b: Vec<u8>,
    le: bool,
}

impl Cdr {
    pub(crate) fn new(le: bool) -> Self {
        Cdr {
            b: vec![0, le as u8, 0, 0],
            le,
        }
    }
    pub(crate) fn align(&mut self, n: usize) {
        while !(self.b.len() - 4).is_multiple_of(n) {
            self.b.push(0);
        }
    }
    pub(crate) fn put(&mut self, le: &[u8], n: usize) {
        self.align(n);
        if self.le {
            self.b.extend_from_slice(le);
        } else {
            self.b.extend(le.iter().rev());
        }
    }
    pub(crate) fn u8(&mut self, v: u8) {
        self.b.push(v);
    }
    pub(crate) fn u32(&mut self, v: u32) {
        self.put(&v.to_le_bytes(), 4);
    }
    pub(crate) fn f32(&mut self, v: f32) {
        self.put(&v.to_le_bytes(), 4);
    }
    pub(crate) fn f64(&mut self, v: f64) {
        self.put(&v.to_le_bytes(), 8);
    }
    pub(crate) fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.b.extend_from_slice(s.as_bytes());
        self.b.push(0);
    }
    pub(crate) fn header(&mut self, t: f64, frame: &str) {
        self.put(&(t.floor() as i32).to_le_bytes(), 4);
        self.u32(((t - t.floor()) * 1e9).round() as u32);
        self.string(frame);
    }
    pub(crate) fn quaternion_yaw(&mut self, yaw: f64) {
        for v in [0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()] {
            self.f64(v);
        }
    }
}

pub(crate) fn range_msg(le: bool, t: f64, frame: &str, range: f32) -> Vec<u8> {
    let mut c = Cdr::new(le);
    c.header(t, frame);
    c.u8(0);
    for v in [0.4363f32, 0.15, 5.0, range] {
        c.f32(v);
    }
    c.b
}

pub(crate) fn odom_msg(t: f64, x: f64, y: f64, yaw: f64) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.header(t, "odom");
    c.string("base_link");
    for v in [x, y, 0.0] {
        c.f64(v);
    }
    c.quaternion_yaw(yaw);
    for _ in 0..36 {
        c.f64(0.0);
    }
    for _ in 0..(6 + 36) {
        c.f64(0.0);
    }
    c.b
}

pub(crate) fn tf_msg(mounts: &[(f64, f64, f64)]) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.u32(mounts.len() as u32);
    for (k, &(x, y, yaw)) in mounts.iter().enumerate() {
        c.header(0.0, "base_link");
        c.string(&format!("sonar_{k}"));
        for v in [x, y, 0.1] {
            c.f64(v);
        }
        c.quaternion_yaw(yaw);
    }
    c.b
}

pub(crate) const MOUNTS: [(f64, f64, f64); 4] = [
    (0.2, 0.0, 0.0),
    (0.0, 0.2, std::f64::consts::FRAC_PI_2),
    (-0.2, 0.0, std::f64::consts::PI - 1e-9),
    (0.0, -0.2, -std::f64::consts::FRAC_PI_2),
];

/// Writes an uncompressed MCAP: /tf_static, odometry at 10 Hz, and 3 firing cycles of 4
/// sonars (one topic each) 20 ms apart within a cycle, cycles 0.25 s apart. Sonar 1 of cycle
/// 1 reads infinity, sonar 2 of cycle 2 reads beyond max_range, sonar 3 of cycle 0 is
/// big-endian; `truncate` cuts one Range message short.
pub(crate) fn write_mcap(with_tf: bool, truncate: bool) -> Vec<u8> {
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let none = BTreeMap::new();
    let range_schema = w
        .add_schema("sensor_msgs/msg/Range", "ros2msg", b"")
        .unwrap();
    let odom_schema = w
        .add_schema("nav_msgs/msg/Odometry", "ros2msg", b"")
        .unwrap();
    let tf_schema = w
        .add_schema("tf2_msgs/msg/TFMessage", "ros2msg", b"")
        .unwrap();
    let other = w.add_schema("std_msgs/msg/String", "ros2msg", b"").unwrap();
    let sonar: Vec<u16> = (0..4)
        .map(|k| {
            w.add_channel(range_schema, &format!("/sonar_{k}"), "cdr", &none)
                .unwrap()
        })
        .collect();
    let odom = w.add_channel(odom_schema, "/odom", "cdr", &none).unwrap();
    let tf = w
        .add_channel(tf_schema, "/tf_static", "cdr", &none)
        .unwrap();
    let chatter = w.add_channel(other, "/chatter", "cdr", &none).unwrap();
    let mut seq = 0;
    let mut put = |w: &mut mcap::Writer<Cursor<Vec<u8>>>, ch: u16, t: f64, data: &[u8]| {
        seq += 1;
        let header = mcap::records::MessageHeader {
            channel_id: ch,
            sequence: seq,
            log_time: (t * 1e9) as u64,
            publish_time: (t * 1e9) as u64,
        };
        w.write_to_known_channel(&header, data).unwrap();
    };
    if with_tf {
        put(&mut w, tf, 10.0, &tf_msg(&MOUNTS));
    }
    put(&mut w, chatter, 10.0, &[0, 1, 0, 0, 1, 0, 0, 0, 0]);
    for i in 0..=8 {
        let t = 10.0 + 0.1 * i as f64;
        put(
            &mut w,
            odom,
            t,
            &odom_msg(t, 0.1 * i as f64, 0.0, 0.05 * i as f64),
        );
    }
    for cycle in 0..3 {
        for (k, &channel) in sonar.iter().enumerate() {
            let t = 10.1 + 0.25 * cycle as f64 + 0.02 * k as f64;
            let mut range = 1.0 + 0.1 * k as f32 + cycle as f32;
            if cycle == 1 && k == 1 {
                range = f32::INFINITY;
            }
            if cycle == 2 && k == 2 {
                range = 7.5;
            }
            let mut data = range_msg(!(cycle == 0 && k == 3), t, &format!("sonar_{k}"), range);
            if truncate && cycle == 1 && k == 2 {
                data.truncate(data.len() - 3);
            }
            put(&mut w, channel, t, &data);
        }
    }
    w.finish().unwrap();
    w.into_inner().into_inner()
}
