//! What the batch tests share: their JSON outputs with the timings masked,
//! so that runs made at other times (or on other ranks) compare bit for bit.

use serde_json::Value;

/// The keys of JSON outputs that hold timings (or, for a study's
/// recommendation, depend on them).
const TIMED_KEYS: &[&str] = &["cpu_s", "wall_s", "speed_up", "cost_s", "recommendation"];

/// `v` with every timing replaced by `null`.
pub fn untimed(mut v: Value) -> Value {
    match &mut v {
        Value::Object(map) => {
            for (k, x) in map.iter_mut() {
                *x = if TIMED_KEYS.contains(&k.as_str()) {
                    Value::Null
                } else {
                    untimed(x.take())
                };
            }
        }
        Value::Array(items) => {
            for x in items.iter_mut() {
                *x = untimed(x.take());
            }
        }
        _ => {}
    }
    v
}
