/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * pnioerrx.h - return codes of procimg's IO-Base compatible API.
 *
 * Written for procimg from the facts of the SIMATIC NET IO-Base programming manual (names
 * and meanings) and the numeric values of the 2015 interface, so that a program written for
 * IO-Base compares the same numbers. Every function returns PNIO_OK on success, a warning
 * PNIO_WARN_* when it did its job with a remark, and an error PNIO_ERR_* otherwise. When
 * libprocimg returns an error it also keeps a text saying what went wrong and what to do
 * for the calling thread (see pniousrx.h). The codes marked PN Driver have the values of PN
 * Driver's public headers: the manual names some of them and prints no value.
 */
#ifndef PNIOERRX_H
#define PNIOERRX_H

/** Success. */
#define PNIO_OK                                  0x000
/** PROFIenergy: the device woke up online. */
#define PNIO_OK_PE_WAKE_ONLINE                   0x001
/** PROFIenergy: the device woke up offline. */
#define PNIO_OK_PE_WAKE_OFFLINE                  0x002
/** IRT data accessed outside the STARTOP..OPDONE window: it may be inconsistent. */
#define PNIO_WARN_IRT_INCONSISTENT               0x010
/** No submodules. */
#define PNIO_WARN_NO_SUBMODULES                  0x011
/** The local state is BAD. */
#define PNIO_WARN_LOCAL_STATE_BAD                0x012
/** PN Driver: the configuration has no IO system of its own. */
#define PNIO_WARN_NO_DECENTRALIOSYSTEM           0x013
/** The handle pointer is NULL. */
#define PNIO_ERR_PRM_HND                         0x101
/** The buffer pointer is NULL (or its length 0). */
#define PNIO_ERR_PRM_BUF                         0x102
/** The length pointer is NULL. */
#define PNIO_ERR_PRM_LEN                         0x103
/** The address is invalid. */
#define PNIO_ERR_PRM_ADD                         0x104
/** The remote-state pointer is NULL. */
#define PNIO_ERR_PRM_RSTATE                      0x105
/** The callback is invalid. */
#define PNIO_ERR_PRM_CALLBACK                    0x106
/** The event type is invalid. */
#define PNIO_ERR_PRM_TYPE                        0x107
/** ExtPar is invalid. */
#define PNIO_ERR_PRM_EXT_PAR                     0x108
/** The IO data type does not fit the function. */
#define PNIO_ERR_PRM_IO_TYPE                     0x109
/** The CpIndex is invalid. */
#define PNIO_ERR_PRM_CP_ID                       0x10A
/** The local state is invalid. */
#define PNIO_ERR_PRM_LOC_STATE                   0x10B
/** The record index is invalid. */
#define PNIO_ERR_PRM_REC_INDEX                   0x10C
/** The timeout is invalid. */
#define PNIO_ERR_PRM_TIMEOUT                     0x10D
/** The device annotation is invalid. */
#define PNIO_ERR_PRM_DEV_ANNOTATION              0x10E
/** The device state is invalid. */
#define PNIO_ERR_PRM_DEV_STATE                   0x10F
/** The callback pointer is invalid. */
#define PNIO_ERR_PRM_PCBF                        0x110
/** The max AR value is invalid. */
#define PNIO_ERR_PRM_MAX_AR_VALUE                0x111
/** The access type is invalid. */
#define PNIO_ERR_PRM_ACCESS_TYPE                 0x112
/** A pointer is invalid. */
#define PNIO_ERR_PRM_POINTER                     0x113
/** An argument is invalid. */
#define PNIO_ERR_PRM_INVALIDARG                  0x114
/** The measurement number is invalid. */
#define PNIO_ERR_PRM_MEASURE_NUMBER              0x115
/** The cycle offset is invalid. */
#define PNIO_ERR_PRM_CYCLE_OFFSET                0x116
/** The router address is invalid. */
#define PNIO_ERR_PRM_ROUTER_ADD                  0x117
/** PN Driver: the IP suite is invalid. */
#define PNIO_ERR_PRM_IP                          0x118
/** PN Driver: the NameOfStation is invalid. */
#define PNIO_ERR_PRM_NOS                         0x119
/** PN Driver: the NameOfStation is too long. */
#define PNIO_ERR_PRM_NOS_LEN                     0x11A
/** The handle is unknown or closed. */
#define PNIO_ERR_WRONG_HND                       0x201
/** No more instances. */
#define PNIO_ERR_MAX_REACHED                     0x202
/** The instance could not be created. */
#define PNIO_ERR_CREATE_INSTANCE                 0x203
/** Not allowed in the current mode, or the mode value is invalid. */
#define PNIO_ERR_MODE_VALUE                      0x204
/** STARTOP registered before OPFAULT. */
#define PNIO_ERR_OPFAULT_NOT_REG                 0x205
/** NEWCYCLE registered in the wrong order. */
#define PNIO_ERR_NEWCYCLE_SEQUENCE_REG           0x206
/** The network protocol is not available. */
#define PNIO_ERR_NETWORK_PROT_NOT_AVAILABLE      0x207
/** PN Driver: the stack is not available yet; try again later. */
#define PNIO_ERR_RETRY                           0x208
/** No connection to the device (or the server). */
#define PNIO_ERR_NO_CONNECTION                   0x301
/** An operating-system resource failed. */
#define PNIO_ERR_OS_RES                          0x302
/** Already done (registered before). */
#define PNIO_ERR_ALREADY_DONE                    0x303
/** The manual's spelling of [`PNIO_ERR_ALREADY_DONE`]. */
#define PNIO_ERR_ALLREADY_DONE                   PNIO_ERR_ALREADY_DONE
/** No configuration (no server for this CP). */
#define PNIO_ERR_NO_CONFIG                       0x304
/** `PNIO_set_mode` is not allowed (open without `PNIO_CEP_MODE_CTRL`). */
#define PNIO_ERR_SET_MODE_NOT_ALLOWED            0x305
/** `PNIO_device_activate` is not allowed (open without `PNIO_CEP_MODE_CTRL`). */
#define PNIO_ERR_DEV_ACT_NOT_ALLOWED             0x306
/** No licence server. */
#define PNIO_ERR_NO_LIC_SERVER                   0x307
/** The length does not fit. */
#define PNIO_ERR_VALUE_LEN                       0x308
/** The call is out of sequence. */
#define PNIO_ERR_SEQUENCE                        0x309
/** The configuration is invalid. */
#define PNIO_ERR_INVALID_CONFIG                  0x30A
/** The address is not configured. */
#define PNIO_ERR_UNKNOWN_ADDR                    0x30B
/** Out of resources. */
#define PNIO_ERR_NO_RESOURCE                     0x30C
/** The configuration is being updated. */
#define PNIO_ERR_CONFIG_IN_UPDATE                0x30D
/** No communication with the firmware (the server). */
#define PNIO_ERR_NO_FW_COMMUNICATION             0x30E
/** STARTOP is not registered. */
#define PNIO_ERR_STARTOP_NOT_REGISTERED          0x30F
/** Owned by another program. */
#define PNIO_ERR_OWNED                           0x310
/** A thread could not be started. */
#define PNIO_ERR_START_THREAD_FAILED             0x311
/** A real-time thread could not be started. */
#define PNIO_ERR_START_RT_THREAD_FAILED          0x312
/** A driver call failed. */
#define PNIO_ERR_DRIVER_IOCTL_FAILED             0x313
/** After an exception. */
#define PNIO_ERR_AFTER_EXCEPTION                 0x314
/** No cycle information. */
#define PNIO_ERR_NO_CYCLE_INFO_DATA              0x315
/** Session error. */
#define PNIO_ERR_SESSION                         0x316
/** Alarm data format error. */
#define PNIO_ERR_ALARM_DATA_FORMAT               0x317
/** Aborted. */
#define PNIO_ERR_ABORT                           0x318
/** Corrupted data. */
#define PNIO_ERR_CORRUPTED_DATA                  0x319
/** Flash access failed. */
#define PNIO_ERR_FLASH_ACCESS                    0x31A
/** Wrong request block length. */
#define PNIO_ERR_WRONG_RQB_LEN                   0x31B
/** No reset verification. */
#define PNIO_ERR_NO_RESET_VERIFICATION           0x31C
/** PN Driver: the configuration does not let the program set the IP suite or NameOfStation. */
#define PNIO_ERR_SET_IP_NOS_NOT_ALLOWED          0x31D
/** PN Driver: the retentive data cannot be read. */
#define PNIO_ERR_INVALID_REMA                    0x31E
/** PN Driver: the previous job of this kind has not ended. */
#define PNIO_ERR_NOT_REENTERABLE                 0x31F
/** PN Driver: the station is not configured as optional (tailoring). */
#define PNIO_ERR_INVALID_STATION                 0x320
/** PN Driver: the port has no programmable peer (tailoring). */
#define PNIO_ERR_INVALID_PORT                    0x321
/** PN Driver: no network adapter found. */
#define PNIO_ERR_NO_ADAPTER_FOUND                0x322
/** PN Driver: access denied. */
#define PNIO_ERR_ACCESS_DENIED                   0x323
/** Internal error. */
#define PNIO_ERR_INTERNAL                        0x3FF

#endif /* PNIOERRX_H */
