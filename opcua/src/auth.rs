// SPDX-License-Identifier: MIT OR Apache-2.0
//! Who a session is and what it may do: anonymous sessions read, users of the users file
//! read (role `reader`) or also write outputs (role `writer`), by user name and password.

use crate::users::{Role, Users};
use async_trait::async_trait;
use opcua::server::ServerEndpoint;
use opcua::server::address_space::AccessLevel;
use opcua::server::authenticator::{
    AuthManager, Password, UserToken, user_pass_security_policy_id,
};
use opcua::types::{
    Error, MessageSecurityMode, NodeId, StatusCode, UAString, UserTokenPolicy, UserTokenType,
};
use std::sync::Arc;

/// The sessions' authenticator.
pub struct Sessions {
    users: Arc<Users>,
}

impl Sessions {
    /// Over `users` (none: anonymous sessions only).
    pub fn new(users: Arc<Users>) -> Sessions {
        Sessions { users }
    }

    /// Whether the session of `token` may write outputs.
    pub fn may_write(users: &Users, token: &UserToken) -> bool {
        !token.is_anonymous() && users.role(&token.0) == Some(Role::Writer)
    }
}

#[async_trait]
impl AuthManager for Sessions {
    async fn authenticate_anonymous_token(&self, _endpoint: &ServerEndpoint) -> Result<(), Error> {
        Ok(())
    }

    async fn authenticate_username_identity_token(
        &self,
        endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        // A password in clear over an endpoint without security is not taken.
        if endpoint.message_security_mode() == MessageSecurityMode::None {
            return Err(Error::new(
                StatusCode::BadIdentityTokenRejected,
                "user names and passwords are taken over a secure endpoint only",
            ));
        }
        match self.users.verify(username, password.get()) {
            Some(_) => Ok(UserToken(username.to_owned())),
            None => Err(Error::new(
                StatusCode::BadUserAccessDenied,
                format!("user {username:?}: unknown, or another password"),
            )),
        }
    }

    fn effective_user_access_level(
        &self,
        token: &UserToken,
        level: AccessLevel,
        _node: &NodeId,
    ) -> AccessLevel {
        if Sessions::may_write(&self.users, token) {
            level
        } else {
            level - AccessLevel::CURRENT_WRITE
        }
    }

    fn is_user_executable(&self, token: &UserToken, method: &NodeId) -> bool {
        let name = match &method.identifier {
            opcua::types::Identifier::String(s) => s.as_ref().to_owned(),
            _ => String::new(),
        };
        let writers_only = crate::methods::WRITER_METHODS
            .iter()
            .any(|m| name.ends_with(m));
        !writers_only || Sessions::may_write(&self.users, token)
    }

    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let mut policies = vec![UserTokenPolicy {
            policy_id: UAString::from("anonymous"),
            token_type: UserTokenType::Anonymous,
            ..Default::default()
        }];
        if !self.users.is_empty() && endpoint.message_security_mode() != MessageSecurityMode::None {
            policies.push(UserTokenPolicy {
                policy_id: user_pass_security_policy_id(endpoint),
                token_type: UserTokenType::UserName,
                ..Default::default()
            });
        }
        policies
    }
}
