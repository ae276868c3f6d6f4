//! The broker's address: `mqtt://[USER[:PASSWORD]@]HOST[:PORT]` (port 1883)
//! or `mqtts://…` (TLS, port 8883), and the client options it gives.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use rumqttc::{LastWill, MqttOptions, QoS, TlsConfiguration, Transport};

/// A parsed broker URL.
#[derive(Clone, PartialEq, Eq)]
pub struct Broker {
    pub host: String,
    pub port: u16,
    pub tls: bool,
    pub user: Option<String>,
    pub password: Option<String>,
}

impl std::fmt::Debug for Broker {
    // Never prints the password.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.display())
    }
}

impl Broker {
    /// Parses `--mqtt URL`.
    pub fn parse(text: &str) -> Result<Broker, String> {
        let bad = |why: &str| format!("--mqtt `{text}`: {why} (e.g. mqtt://127.0.0.1:1883)");
        if !text.contains("://") {
            return Err(bad("expected mqtt://HOST[:PORT] or mqtts://HOST[:PORT]"));
        }
        let url = url::Url::parse(text).map_err(|e| bad(&e.to_string()))?;
        let tls = match url.scheme() {
            "mqtt" | "tcp" => false,
            "mqtts" | "ssl" => true,
            other => return Err(bad(&format!("scheme `{other}` is not mqtt or mqtts"))),
        };
        let host = url
            .host_str()
            .filter(|h| !h.is_empty())
            .ok_or_else(|| bad("no host"))?
            .trim_start_matches('[')
            .trim_end_matches(']')
            .to_string();
        if !matches!(url.path(), "" | "/") || url.query().is_some() || url.fragment().is_some() {
            return Err(bad(
                "only scheme, user, host and port; the topic prefix is --mqtt-topic",
            ));
        }
        let decode = |s: &str| {
            url::form_urlencoded::parse(format!("x={s}").as_bytes())
                .next()
                .map(|(_, v)| v.into_owned())
                .unwrap_or_default()
        };
        let user = (!url.username().is_empty()).then(|| decode(url.username()));
        let password = url.password().map(decode);
        Ok(Broker {
            host,
            port: url.port().unwrap_or(if tls { 8883 } else { 1883 }),
            tls,
            user,
            password,
        })
    }

    /// The URL without the password, for messages.
    pub fn display(&self) -> String {
        let user = self
            .user
            .as_ref()
            .map_or(String::new(), |u| format!("{u}@"));
        let host = if self.host.contains(':') {
            format!("[{}]", self.host)
        } else {
            self.host.clone()
        };
        let scheme = if self.tls { "mqtts" } else { "mqtt" };
        format!("{scheme}://{user}{host}:{}", self.port)
    }

    /// The client options: `$state` as the last will (`offline`, retained),
    /// credentials, and TLS with the system's root certificates or `ca`.
    pub fn options(
        &self,
        client_id: &str,
        state_topic: &str,
        ca: Option<&Path>,
    ) -> Result<MqttOptions, String> {
        let mut o = MqttOptions::new(client_id, &self.host, self.port);
        o.set_keep_alive(Duration::from_secs(5));
        o.set_clean_session(true);
        o.set_last_will(LastWill::new(
            state_topic,
            "offline",
            QoS::AtLeastOnce,
            true,
        ));
        if let Some(u) = &self.user {
            o.set_credentials(u, self.password.clone().unwrap_or_default());
        }
        if self.tls {
            o.set_transport(Transport::tls_with_config(tls_config(ca)?));
        } else if ca.is_some() {
            return Err("--mqtt-ca needs an mqtts:// broker".into());
        }
        Ok(o)
    }
}

/// A rustls client configuration (the ring provider) trusting `ca` (PEM) or,
/// without it, the system's root certificates.
fn tls_config(ca: Option<&Path>) -> Result<TlsConfiguration, String> {
    let mut roots = rustls::RootCertStore::empty();
    match ca {
        Some(path) => {
            let pem =
                std::fs::read(path).map_err(|e| format!("--mqtt-ca {}: {e}", path.display()))?;
            let mut any = false;
            for cert in rustls_pemfile::certs(&mut pem.as_slice()) {
                let cert = cert.map_err(|e| format!("--mqtt-ca {}: {e}", path.display()))?;
                roots
                    .add(cert)
                    .map_err(|e| format!("--mqtt-ca {}: {e}", path.display()))?;
                any = true;
            }
            if !any {
                return Err(format!(
                    "--mqtt-ca {}: no PEM certificate in it",
                    path.display()
                ));
            }
        }
        None => {
            let found = rustls_native_certs::load_native_certs();
            for cert in found.certs {
                let _ = roots.add(cert);
            }
            if roots.is_empty() {
                return Err(
                    "mqtts://: no root certificates on this system; give the broker's CA with --mqtt-ca FILE"
                        .into(),
                );
            }
        }
    }
    // ring builds with a C compiler alone (aws-lc needs more); its lack of
    // post-quantum key exchange is what the deprecation is about.
    #[allow(deprecated)]
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let config = rustls::ClientConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .map_err(|e| format!("mqtts://: {e}"))?
        .with_root_certificates(roots)
        .with_no_client_auth();
    Ok(TlsConfiguration::Rustls(Arc::new(config)))
}

/// The default client id: the host's name and the process id, so two
/// servers never take each other's session.
pub fn default_client_id() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_default();
    let host: String = host
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || *c == '-')
        .take(40)
        .collect();
    format!("softplc-{host}-{}", std::process::id())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_with_defaults_credentials_and_errors() {
        let b = Broker::parse("mqtt://127.0.0.1").unwrap();
        assert_eq!((b.host.as_str(), b.port, b.tls), ("127.0.0.1", 1883, false));
        let b = Broker::parse("mqtts://plc%40line:p%3Ass@broker.example:9883").unwrap();
        assert_eq!(
            (b.host.as_str(), b.port, b.tls),
            ("broker.example", 9883, true)
        );
        assert_eq!(b.user.as_deref(), Some("plc@line"));
        assert_eq!(b.password.as_deref(), Some("p:ss"));
        assert_eq!(b.display(), "mqtts://plc@line@broker.example:9883");
        assert!(!format!("{b:?}").contains("p:ss"));
        let b = Broker::parse("mqtt://[::1]:1884").unwrap();
        assert_eq!((b.host.as_str(), b.port), ("::1", 1884));
        assert_eq!(b.display(), "mqtt://[::1]:1884");
        for (bad, why) in [
            ("127.0.0.1:1883", "expected mqtt://HOST[:PORT]"),
            ("http://h", "scheme `http`"),
            ("mqtt://h/plant", "the topic prefix is --mqtt-topic"),
            ("mqtt://", "--mqtt `mqtt://`"),
        ] {
            let e = Broker::parse(bad).unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    #[test]
    fn a_ca_file_needs_tls_and_must_hold_a_certificate() {
        let plain = Broker::parse("mqtt://h").unwrap();
        let e = plain
            .options("id", "p/$state", Some(Path::new("/nonexistent")))
            .unwrap_err();
        assert!(e.contains("needs an mqtts://"), "{e}");
        let tls = Broker::parse("mqtts://h").unwrap();
        let dir = std::env::temp_dir().join(format!("softplc-mqtt-ca-{}", std::process::id()));
        std::fs::write(&dir, "not a certificate\n").unwrap();
        let e = tls.options("id", "p/$state", Some(&dir)).unwrap_err();
        let _ = std::fs::remove_file(&dir);
        assert!(e.contains("no PEM certificate"), "{e}");
    }
}
