//! `softplc serve --mqtt URL` (contract §8): the chosen devices published to
//! an MQTT broker at the END where they change, retained, as
//! `PREFIX/DEV` = `{"value": 5, "scan": 1234}` (all of them once after each
//! connect); `PREFIX/$state` is `online` while connected and `offline` as
//! the last will. With `--mqtt-write`, `{"value": 7}` published to
//! `PREFIX/set/DEV` is written at the next END like an HTTP write; a bad
//! name or value is logged and ignored.
//!
//! The broker is a client's business: the engine thread only samples the
//! devices at END into [`feed::Feed`]; the task here connects, reconnects
//! with backoff, and sends what changed. A broker that is down or slow never
//! stalls the scan.

pub mod broker;
pub mod feed;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use rumqttc::{AsyncClient, Event, Packet, QoS};
use serde_json::{json, Value as Json};
use softplc_core::names::Names;
use softplc_http::values::{dev, to_json, Dev};
use softplc_serve::{EngineHandle, Listener, ServeState};

pub use broker::Broker;
use feed::{Feed, Sample};

/// What `serve --mqtt…` asks for.
#[derive(Debug, Clone)]
pub struct MqttConfig {
    pub broker: Broker,
    /// Topic prefix, without a trailing `/`.
    pub prefix: String,
    /// Device names as `--show` takes them (`CPU2/D0` in a system).
    pub publish: Vec<String>,
    /// Accept writes on `PREFIX/set/DEV`.
    pub write: bool,
    pub client_id: String,
    /// CA certificate (PEM) of an `mqtts://` broker; else the system's roots.
    pub ca: Option<PathBuf>,
}

/// Checks a topic prefix: MQTT forbids wildcards in a published topic.
pub fn check_prefix(prefix: &str) -> Result<String, String> {
    let p = prefix.trim().trim_end_matches('/');
    if p.is_empty() {
        return Err("--mqtt-topic: an empty topic prefix".into());
    }
    if p.contains(['+', '#', '\0']) {
        return Err(format!(
            "--mqtt-topic `{prefix}`: `+`, `#` and NUL are not allowed in a topic"
        ));
    }
    Ok(p.to_string())
}

/// The checked configuration with its devices resolved against the CPUs.
pub struct Prepared {
    cfg: MqttConfig,
    feed: Arc<Feed>,
    names: Vec<Names>,
    options: rumqttc::MqttOptions,
}

impl Prepared {
    /// Resolves the published names on the served CPUs; an unknown name, a
    /// bad prefix or TLS file is an error naming it.
    pub fn new(cfg: MqttConfig, s: &ServeState) -> Result<Prepared, String> {
        let names: Vec<Names> = (0..s.cpu_count()).map(|i| Names::of(s.cpu_at(i))).collect();
        if cfg.publish.is_empty() && !cfg.write {
            return Err("--mqtt: name the devices to publish with --mqtt-publish DEV,DEV… (or accept writes with --mqtt-write)".into());
        }
        let mut points = Vec::with_capacity(cfg.publish.len());
        for text in &cfg.publish {
            let d = dev(text, &names).map_err(|e| format!("--mqtt-publish: {e}"))?;
            if points.iter().any(|p: &Dev| p.text() == d.text()) {
                return Err(format!("--mqtt-publish: `{}` is listed twice", d.text()));
            }
            points.push(d);
        }
        let state_topic = format!("{}/$state", cfg.prefix);
        let options = cfg
            .broker
            .options(&cfg.client_id, &state_topic, cfg.ca.as_deref())?;
        Ok(Prepared {
            feed: Feed::new(points),
            names,
            cfg,
            options,
        })
    }

    /// The task started with the servers (it binds nothing).
    pub fn listener(self) -> Listener {
        Listener::client(move |engine| tokio::spawn(run(self, engine)))
    }
}

const BACKOFF_MIN: Duration = Duration::from_millis(250);
const BACKOFF_MAX: Duration = Duration::from_secs(30);

/// Connects, publishes and takes writes until the runtime stops.
async fn run(p: Prepared, engine: EngineHandle) {
    let Prepared {
        cfg,
        feed,
        names,
        options,
    } = p;
    let hook = feed.clone();
    if engine
        .at_end(move |s| feed::install(s, hook))
        .await
        .is_err()
    {
        return;
    }
    let writes = cfg.write.then(|| {
        let (tx, rx) = tokio::sync::mpsc::channel::<(Dev, softplc_core::access::Value)>(256);
        tokio::spawn(write_at_end(rx, engine.clone()));
        tx
    });
    let (client, mut events) = AsyncClient::new(options, 1024);
    let state_topic = format!("{}/$state", cfg.prefix);
    let set_prefix = format!("{}/set/", cfg.prefix);
    let mut connected = false;
    let mut backoff = BACKOFF_MIN;
    let mut told_down = false;
    let mut log = RateLimited::default();
    let mut out = Vec::new();
    loop {
        tokio::select! {
            ev = events.poll() => match ev {
                Ok(Event::Incoming(Packet::ConnAck(_))) => {
                    connected = true;
                    backoff = BACKOFF_MIN;
                    told_down = false;
                    eprintln!("softplc: --mqtt: connected to {}", cfg.broker.display());
                    let _ = client.try_publish(&state_topic, QoS::AtLeastOnce, true, "online");
                    if cfg.write {
                        let _ = client.try_subscribe(format!("{set_prefix}#"), QoS::AtLeastOnce);
                    }
                    feed.mark_all();
                }
                Ok(Event::Incoming(Packet::Publish(m))) => {
                    if let (Some(tx), Some(name)) = (&writes, m.topic.strip_prefix(&set_prefix)) {
                        match set_request(name, &m.payload, &names) {
                            Ok(w) => {
                                if tx.try_send(w).is_err() {
                                    log.say(&format!("--mqtt-write: {name}: too many writes waiting; dropped"));
                                }
                            }
                            Err(e) => log.say(&format!("--mqtt-write: {}: {e}", m.topic)),
                        }
                    }
                }
                Ok(_) => {}
                Err(e) => {
                    if connected || !told_down {
                        eprintln!(
                            "softplc: --mqtt: {}: {e}; retrying with backoff (at least every {} s)",
                            cfg.broker.display(),
                            BACKOFF_MAX.as_secs()
                        );
                        told_down = true;
                    }
                    connected = false;
                    tokio::time::sleep(backoff).await;
                    backoff = (backoff * 2).min(BACKOFF_MAX);
                }
            },
            _ = feed.wake.notified(), if connected => {}
        }
        if connected {
            send_changed(&client, &feed, &cfg.prefix, &mut out);
        }
    }
}

/// Sends every marked point; one the client cannot take now stays marked
/// (sent after the next event).
fn send_changed(client: &AsyncClient, feed: &Feed, prefix: &str, out: &mut Vec<(usize, Sample)>) {
    feed.take(out);
    for (k, s) in out.drain(..) {
        let topic = format!("{prefix}/{}", feed.points[k].text());
        let payload = json!({"value": to_json(&s.value), "scan": s.scan}).to_string();
        if client
            .try_publish(topic, QoS::AtLeastOnce, true, payload)
            .is_err()
        {
            feed.retry(k);
        }
    }
}

/// A write from `PREFIX/set/NAME` with payload `{"value": V}`.
fn set_request(
    name: &str,
    payload: &[u8],
    names: &[Names],
) -> Result<(Dev, softplc_core::access::Value), String> {
    let d = dev(name, names)?;
    let body: Json = serde_json::from_slice(payload)
        .map_err(|e| format!("not JSON ({e}); expected {{\"value\": …}}"))?;
    let v = body
        .as_object()
        .and_then(|o| o.get("value"))
        .ok_or("expected {\"value\": …}")?;
    let v = d.value(v)?;
    Ok((d, v))
}

/// Applies the writes in the order they came, each at an END, like an
/// HTTP write (committed before the END's replies).
async fn write_at_end(
    mut rx: tokio::sync::mpsc::Receiver<(Dev, softplc_core::access::Value)>,
    engine: EngineHandle,
) {
    while let Some((d, v)) = rx.recv().await {
        let text = d.text().to_string();
        let r = engine
            .at_end(move |s: &mut ServeState| {
                d.write_value(s, &v)?;
                s.mark_wrote(d.cpu);
                Ok::<(), String>(())
            })
            .await;
        match r {
            Ok(Ok(())) => {}
            Ok(Err(e)) => eprintln!("softplc: --mqtt-write: {text}: {e}"),
            Err(e) => eprintln!("softplc: --mqtt-write: {text}: {e}"),
        }
    }
}

/// At most one log line a second; says how many were left out.
#[derive(Default)]
struct RateLimited {
    last: Option<Instant>,
    skipped: u64,
}

impl RateLimited {
    fn say(&mut self, line: &str) {
        if self
            .last
            .is_some_and(|t| t.elapsed() < Duration::from_secs(1))
        {
            self.skipped += 1;
            return;
        }
        if self.skipped > 0 {
            eprintln!("softplc: {line} (and {} more left out)", self.skipped);
        } else {
            eprintln!("softplc: {line}");
        }
        self.skipped = 0;
        self.last = Some(Instant::now());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_without_wildcards() {
        assert_eq!(check_prefix("plant/line1/").unwrap(), "plant/line1");
        assert!(check_prefix("plant/#").unwrap_err().contains("not allowed"));
        assert!(check_prefix("a/+/b").unwrap_err().contains("not allowed"));
        assert!(check_prefix(" ").unwrap_err().contains("empty"));
    }
}
