// SPDX-License-Identifier: MIT OR Apache-2.0
//! The coded values of AgentX: PDU types (RFC 2741 §6.1), Close reasons (§6.2.2) and the
//! error codes of a Response (§6.2.16), each with an `Unknown` catch-all so that every raw
//! value parses and round-trips.

use coded_enum::coded_enum;

coded_enum! {
    /// h.type: what a PDU is (RFC 2741 §6.1).
    pub enum PduType(u8) display "type {}" {
        /// A subagent asks to open a session.
        Open = 1 => "Open",
        /// Either side ends a session.
        Close = 2 => "Close",
        /// A subagent registers a subtree.
        Register = 3 => "Register",
        /// A subagent withdraws a registration.
        Unregister = 4 => "Unregister",
        /// The master asks for values.
        Get = 5 => "Get",
        /// The master asks for the next values in a range.
        GetNext = 6 => "GetNext",
        /// The master asks for repeated next values.
        GetBulk = 7 => "GetBulk",
        /// First phase of a set.
        TestSet = 8 => "TestSet",
        /// Second phase of a set.
        CommitSet = 9 => "CommitSet",
        /// Undo of a committed set.
        UndoSet = 10 => "UndoSet",
        /// End of a set; never answered.
        CleanupSet = 11 => "CleanupSet",
        /// A subagent sends a notification.
        Notify = 12 => "Notify",
        /// A subagent checks that the master is there.
        Ping = 13 => "Ping",
        /// A subagent allocates index values.
        IndexAllocate = 14 => "IndexAllocate",
        /// A subagent releases index values.
        IndexDeallocate = 15 => "IndexDeallocate",
        /// A subagent adds agent capabilities.
        AddAgentCaps = 16 => "AddAgentCaps",
        /// A subagent removes agent capabilities.
        RemoveAgentCaps = 17 => "RemoveAgentCaps",
        /// The answer to every other PDU but CleanupSet.
        Response = 18 => "Response",
    }
}

impl PduType {
    /// Whether a PDU of this type carries a context when NON_DEFAULT_CONTEXT is set
    /// (RFC 2741 §6.1.1).
    pub const fn carries_context(self) -> bool {
        matches!(
            self,
            PduType::Register
                | PduType::Unregister
                | PduType::Get
                | PduType::GetNext
                | PduType::GetBulk
                | PduType::TestSet
                | PduType::Notify
                | PduType::Ping
                | PduType::IndexAllocate
                | PduType::IndexDeallocate
                | PduType::AddAgentCaps
                | PduType::RemoveAgentCaps
        )
    }
}

coded_enum! {
    /// c.reason: why a session is closed (RFC 2741 §6.2.2).
    pub enum CloseReason(u8) display "reason {}" {
        /// None of the others.
        Other = 1 => "reasonOther",
        /// The peer sent a PDU that could not be parsed.
        ParseError = 2 => "reasonParseError",
        /// The peer broke the protocol.
        ProtocolError = 3 => "reasonProtocolError",
        /// Too many requests timed out.
        Timeouts = 4 => "reasonTimeouts",
        /// The sender is shutting down.
        Shutdown = 5 => "reasonShutdown",
        /// A management request closed it.
        ByManager = 6 => "reasonByManager",
    }
}

coded_enum! {
    /// res.error: the outcome a Response reports (RFC 2741 §6.2.16: the SNMP error
    /// statuses of RFC 3416 and AgentX's own from 256 on).
    pub enum ResponseError(u16) display "error {}" {
        /// Success.
        NoError = 0 => "noError",
        /// SNMP tooBig.
        TooBig = 1 => "tooBig",
        /// SNMP noSuchName.
        NoSuchName = 2 => "noSuchName",
        /// SNMP badValue.
        BadValue = 3 => "badValue",
        /// SNMP readOnly.
        ReadOnly = 4 => "readOnly",
        /// SNMP genErr.
        GenErr = 5 => "genErr",
        /// SNMP noAccess.
        NoAccess = 6 => "noAccess",
        /// SNMP wrongType.
        WrongType = 7 => "wrongType",
        /// SNMP wrongLength.
        WrongLength = 8 => "wrongLength",
        /// SNMP wrongEncoding.
        WrongEncoding = 9 => "wrongEncoding",
        /// SNMP wrongValue.
        WrongValue = 10 => "wrongValue",
        /// SNMP noCreation.
        NoCreation = 11 => "noCreation",
        /// SNMP inconsistentValue.
        InconsistentValue = 12 => "inconsistentValue",
        /// SNMP resourceUnavailable.
        ResourceUnavailable = 13 => "resourceUnavailable",
        /// SNMP commitFailed.
        CommitFailed = 14 => "commitFailed",
        /// SNMP undoFailed.
        UndoFailed = 15 => "undoFailed",
        /// SNMP authorizationError.
        AuthorizationError = 16 => "authorizationError",
        /// SNMP notWritable: what a read-only MIB answers to TestSet.
        NotWritable = 17 => "notWritable",
        /// SNMP inconsistentName.
        InconsistentName = 18 => "inconsistentName",
        /// The master refused to open the session.
        OpenFailed = 256 => "openFailed",
        /// The session named in the header is not open.
        NotOpen = 257 => "notOpen",
        /// IndexAllocate: wrong index type.
        IndexWrongType = 258 => "indexWrongType",
        /// IndexAllocate: index in use.
        IndexAlreadyAllocated = 259 => "indexAlreadyAllocated",
        /// IndexAllocate: none left.
        IndexNoneAvailable = 260 => "indexNoneAvailable",
        /// IndexDeallocate: not allocated.
        IndexNotAllocated = 261 => "indexNotAllocated",
        /// The context is not supported.
        UnsupportedContext = 262 => "unsupportedContext",
        /// The subtree is registered already (same subtree, context and priority).
        DuplicateRegistration = 263 => "duplicateRegistration",
        /// Unregister: no such registration.
        UnknownRegistration = 264 => "unknownRegistration",
        /// RemoveAgentCaps: no such capabilities.
        UnknownAgentCaps = 265 => "unknownAgentCaps",
        /// The PDU could not be parsed.
        ParseError = 266 => "parseError",
        /// The master denies the request.
        RequestDenied = 267 => "requestDenied",
        /// The master could not process it.
        ProcessingError = 268 => "processingError",
    }
}
