/**
 * Radiant's internals: the node tree of a chain and the compiler that turns it into one class.
 * Not an API: it may change in any release.
 */
package dev.prime.radiant.internal;
