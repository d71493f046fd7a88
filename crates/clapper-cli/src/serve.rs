//! `clapper serve`: the web application on a local port.

use std::io::Write as _;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};

use anyhow::{Context, Result};
use clap::Args;
use clapper_web::Limits;

#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Port to listen on (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Address to listen on. The default, loopback, is reachable only from
    /// this machine; give 0.0.0.0 to share it on a network you trust.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    pub host: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Computations running at once (further requests wait).
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_jobs)]
    pub max_jobs: usize,
    /// Most chart points in one chart request.
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_chart_points)]
    pub max_chart_points: usize,
    /// Also answer requests to this host name (repeatable; `*.example.org`
    /// for every name under it). Loopback names and IP addresses are
    /// always answered; any other name is refused (403), so that a web page
    /// elsewhere cannot drive this server through your browser.
    #[arg(long, value_name = "NAME")]
    pub allow_host: Vec<String>,
}

pub fn run(args: ServeArgs) -> Result<()> {
    if args.max_jobs == 0 || args.max_jobs > 1024 {
        anyhow::bail!("--max-jobs {} is out of range: 1 to 1024", args.max_jobs);
    }
    if args.max_chart_points == 0 || args.max_chart_points > clapper_core::chart::MAX_POINTS {
        anyhow::bail!(
            "--max-chart-points {} is out of range: 1 to {}",
            args.max_chart_points,
            clapper_core::chart::MAX_POINTS
        );
    }
    let hosts = clapper_web::AllowedHosts::with(&args.allow_host).map_err(anyhow::Error::msg)?;
    let limits = Limits {
        max_jobs: args.max_jobs,
        max_chart_points: args.max_chart_points,
        ..Limits::default()
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    let served = runtime.block_on(async move {
        let addr = SocketAddr::new(args.host, args.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .with_context(|| format!("cannot listen on {addr} (is the port in use? try --port 0)"))?;
        let local = listener.local_addr()?;
        let url = format!("http://{local}/");
        println!("clapper is serving on {url}  (API: {url}api; Ctrl-C to stop)");
        std::io::stdout().flush()?;
        if !args.host.is_loopback() {
            eprintln!("warning: listening on {} is reachable from other machines", args.host);
        }
        if args.open {
            open_browser(&url);
        }
        let shutdown = async {
            let _ = tokio::signal::ctrl_c().await;
        };
        clapper_web::serve(listener, limits, hosts, shutdown).await?;
        println!("stopped");
        Ok(())
    });
    // A computation still running (a chart past its client) is not waited
    // for: the process is ending.
    runtime.shutdown_timeout(std::time::Duration::from_millis(200));
    served
}

/// Ask the desktop to open `url`; say so if it cannot.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if std::process::Command::new(opener).arg(url).spawn().is_err() {
        eprintln!("could not open a browser ({opener}); open {url} yourself");
    }
}
