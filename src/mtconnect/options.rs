//! The command-line values of `--mtconnect` and `--mtconnect-wait`.

use std::net::{IpAddr, Ipv4Addr, SocketAddr};

/// The port `--mtconnect` listens on when only an address is given.
pub const DEFAULT_PORT: u16 = 7878;

/// Parses `--mtconnect`'s value: `PORT` (loopback), `ADDR:PORT`, `ADDR` (port 7878), or
/// `[V6]:PORT`.
pub fn parse_addr(v: &str) -> Result<SocketAddr, String> {
    let v = v.trim();
    if v.is_empty() {
        return Err("--mtconnect needs ADDR:PORT or PORT".into());
    }
    if let Ok(port) = v.parse::<u16>() {
        return Ok(SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), port));
    }
    if let Ok(a) = v.parse::<SocketAddr>() {
        return Ok(a);
    }
    if let Ok(ip) = v.parse::<IpAddr>() {
        return Ok(SocketAddr::new(ip, DEFAULT_PORT));
    }
    Err(format!(
        "--mtconnect '{v}': expected PORT (0-65535), ADDR or ADDR:PORT with a numeric address"
    ))
}

/// Parses `--mtconnect-wait`'s value: seconds, 0 to 86400, decimals allowed.
pub fn parse_wait(v: &str) -> Result<std::time::Duration, String> {
    match v.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && (0.0..=86400.0).contains(&s) => {
            Ok(std::time::Duration::from_secs_f64(s))
        }
        _ => Err(format!(
            "--mtconnect-wait '{v}': expected seconds from 0 to 86400"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_and_waits() {
        assert_eq!(parse_addr("7000").unwrap().to_string(), "127.0.0.1:7000");
        assert_eq!(parse_addr("0.0.0.0:1").unwrap().to_string(), "0.0.0.0:1");
        assert_eq!(parse_addr("10.0.0.1").unwrap().to_string(), "10.0.0.1:7878");
        assert_eq!(parse_addr("[::1]:9").unwrap().to_string(), "[::1]:9");
        for bad in ["", "70000", "host:1", "1.2.3.4:x", "-1"] {
            assert!(parse_addr(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_wait("1.5").unwrap().as_millis(), 1500);
        for bad in ["", "-1", "nan", "inf", "1e9", "x"] {
            assert!(parse_wait(bad).is_err(), "{bad}");
        }
    }
}
