//! Which Host (and Origin) names the server answers: a defence against DNS
//! rebinding, where a web page the user visits points its own domain name
//! at 127.0.0.1 and drives the local API from the user's browser. Such a
//! request carries the attacker's name in its Host header (and Origin), so
//! only names that cannot be rebound are served: `localhost` and names
//! under `.localhost` (RFC 6761: always loopback), IP address literals (a
//! page can only reach an IP literal the user typed; rebinding needs a
//! name), and the names given with `--allow-host`. docs/reliability.md
//! says why no per-launch token was added.

use axum::extract::{Request, State};
use axum::http::header::{HOST, ORIGIN};
use axum::http::HeaderMap;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::ApiError;

/// The names the server answers besides loopback names and IP literals.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AllowedHosts {
    names: Vec<String>,
}

/// Longest name quoted back in a refusal (characters): a long header is cut.
const QUOTE_MAX: usize = 80;

impl AllowedHosts {
    /// Loopback names and IP literals only.
    pub fn loopback() -> Self {
        Self::default()
    }

    /// Also `names` (host names without a port, any case; `*.example.org`
    /// for every name under it). A name that is empty or holds a port,
    /// a scheme or a path is refused with the reason.
    pub fn with(names: &[String]) -> Result<Self, String> {
        let mut out = Self::default();
        for n in names {
            let n = n.trim().to_ascii_lowercase();
            let bare = n.strip_prefix("*.").unwrap_or(&n);
            if bare.is_empty() || !bare.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '.') {
                return Err(format!(
                    "--allow-host {}: a host name such as bells.example.org (no scheme, port or path)",
                    quote(&n)
                ));
            }
            out.names.push(n);
        }
        Ok(out)
    }

    /// Whether `host` (a Host header's value or an Origin's authority,
    /// with or without a port) is served.
    pub fn allows(&self, host: &str) -> bool {
        let name = strip_port(host).to_ascii_lowercase();
        if name.is_empty() {
            return false;
        }
        if name == "localhost" || name.ends_with(".localhost") {
            return true;
        }
        let literal = name.trim_start_matches('[').trim_end_matches(']');
        if literal.parse::<std::net::IpAddr>().is_ok() {
            return true;
        }
        self.names.iter().any(|n| match n.strip_prefix("*.") {
            Some(domain) => name.ends_with(&format!(".{domain}")),
            None => *n == name,
        })
    }

    /// Why the request's Host or Origin is refused, if it is. A request
    /// without a Host header is not from a browser (browsers always send
    /// one) and is answered.
    fn refusal(&self, headers: &HeaderMap) -> Option<String> {
        if let Some(h) = headers.get(HOST) {
            let h = h.to_str().unwrap_or("");
            if !self.allows(h) {
                return Some(format!(
                    "host {} is not served here: open the page at localhost or an IP address, \
                     or start the server with --allow-host NAME",
                    quote(h)
                ));
            }
        }
        if let Some(o) = headers.get(ORIGIN) {
            let o = o.to_str().unwrap_or("");
            let authority = o
                .strip_prefix("http://")
                .or_else(|| o.strip_prefix("https://"))
                .map(|rest| rest.split('/').next().unwrap_or(""));
            if !authority.is_some_and(|a| self.allows(a)) {
                return Some(format!(
                    "requests from pages at {} are not served here (only this server's own page, \
                     or a name given with --allow-host)",
                    quote(o)
                ));
            }
        }
        None
    }
}

/// `host` without its `:port` (an IPv6 literal keeps its brackets).
fn strip_port(host: &str) -> &str {
    if let Some(end) = host.find(']') {
        return &host[..=end];
    }
    match host.rsplit_once(':') {
        Some((name, port)) if port.chars().all(|c| c.is_ascii_digit()) => name,
        _ => host,
    }
}

/// `s` for a message: at most [`QUOTE_MAX`] characters, cut with "...".
fn quote(s: &str) -> String {
    if s.chars().count() <= QUOTE_MAX {
        format!("\"{s}\"")
    } else {
        let cut: String = s.chars().take(QUOTE_MAX).collect();
        format!("\"{cut}...\"")
    }
}

/// The middleware: 403 with the reason for a Host or Origin not served.
pub(crate) async fn check(State(hosts): State<AllowedHosts>, req: Request, next: Next) -> Response {
    match hosts.refusal(req.headers()) {
        Some(why) => ApiError::Forbidden(why).into_response(),
        None => next.run(req).await,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_names_and_ip_literals_are_served_and_other_names_not() {
        let h = AllowedHosts::loopback();
        for ok in [
            "localhost",
            "localhost:8080",
            "LocalHost:1",
            "app.localhost:8080",
            "127.0.0.1:8080",
            "10.1.2.3",
            "[::1]:8080",
            "[::1]",
        ] {
            assert!(h.allows(ok), "{ok}");
        }
        for bad in [
            "evil.com",
            "evil.com:8080",
            "localhost.evil.com",
            "",
            ":8080",
            "127.0.0.1.nip.io",
        ] {
            assert!(!h.allows(bad), "{bad}");
        }
        let h = AllowedHosts::with(&["Bells.Example".into(), "*.tower.org".into()]).unwrap();
        assert!(h.allows("bells.example:80") && h.allows("a.tower.org") && !h.allows("tower.org"));
        assert!(AllowedHosts::with(&["http://x".into()]).is_err());
        assert!(AllowedHosts::with(&["x:80".into()]).is_err());
    }

    #[test]
    fn a_long_name_is_cut_in_the_message() {
        let mut headers = HeaderMap::new();
        headers.insert(HOST, "a".repeat(5000).parse().unwrap());
        let why = AllowedHosts::loopback().refusal(&headers).unwrap();
        assert!(why.len() < 300, "{why}");
    }
}
