//! Errors as HTTP answers: a status and `{"error": "one line"}`.

use axum::http::{Method, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use axum::Json;
use clapper_app::AppError;

/// Why a request failed, as the client sees it.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    /// The request is malformed or out of range (400).
    #[error("{0}")]
    BadRequest(String),
    /// The request is well formed but beyond this server's limits (413 or 400).
    #[error("{1}")]
    Limit(StatusCode, String),
    /// The computation failed for valid input (422).
    #[error("{0}")]
    Failed(String),
    /// The request's Host or Origin is not served (403).
    #[error("{0}")]
    Forbidden(String),
    /// No such route (404).
    #[error("{0}")]
    NotFound(String),
    /// The route exists with other methods (405).
    #[error("{0}")]
    MethodNotAllowed(String),
    /// Too busy or too slow (503); try again later.
    #[error("{0}")]
    Unavailable(String),
    /// A fault of the server itself (500).
    #[error("{0}")]
    Internal(String),
}

impl ApiError {
    fn status(&self) -> StatusCode {
        match self {
            ApiError::BadRequest(_) => StatusCode::BAD_REQUEST,
            ApiError::Limit(s, _) => *s,
            ApiError::Failed(_) => StatusCode::UNPROCESSABLE_ENTITY,
            ApiError::Forbidden(_) => StatusCode::FORBIDDEN,
            ApiError::NotFound(_) => StatusCode::NOT_FOUND,
            ApiError::MethodNotAllowed(_) => StatusCode::METHOD_NOT_ALLOWED,
            ApiError::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            ApiError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl From<AppError> for ApiError {
    fn from(e: AppError) -> Self {
        if e.is_bad_input() {
            ApiError::BadRequest(e.to_string())
        } else if matches!(e, AppError::Simulation(_)) {
            ApiError::Failed(e.to_string())
        } else {
            ApiError::Internal(e.to_string())
        }
    }
}

impl From<clapper_core::bell::ParamError> for ApiError {
    fn from(e: clapper_core::bell::ParamError) -> Self {
        ApiError::BadRequest(e.to_string())
    }
}

impl From<axum::extract::rejection::JsonRejection> for ApiError {
    fn from(r: axum::extract::rejection::JsonRejection) -> Self {
        let status = r.status();
        let text = r.body_text().replace('\n', " ");
        if status == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::Limit(status, format!("request body too large: {text}"))
        } else if status == StatusCode::UNSUPPORTED_MEDIA_TYPE {
            ApiError::Limit(
                status,
                format!("{text} (send JSON with Content-Type: application/json)"),
            )
        } else {
            ApiError::BadRequest(text)
        }
    }
}

impl From<axum::extract::rejection::QueryRejection> for ApiError {
    fn from(r: axum::extract::rejection::QueryRejection) -> Self {
        ApiError::BadRequest(r.body_text().replace('\n', " "))
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.status(), Json(serde_json::json!({ "error": self.to_string() }))).into_response()
    }
}

/// Answer for a route that does not exist.
pub(crate) async fn not_found(method: Method, uri: Uri) -> ApiError {
    ApiError::NotFound(format!(
        "no route {method} {}: the page is at /, the API is described at /api",
        uri.path()
    ))
}

/// Answer for a route asked with the wrong method.
pub(crate) async fn method_not_allowed(method: Method, uri: Uri) -> ApiError {
    ApiError::MethodNotAllowed(format!(
        "{} does not take {method}: see /api for each route's method",
        uri.path()
    ))
}
