package com.acme.robot.inner

/** In a subpackage of an allowed package: not allowed by it. */
@JvmRecord
public data class Hidden(val secret: String)
