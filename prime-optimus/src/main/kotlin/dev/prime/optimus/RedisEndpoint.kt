package dev.prime.optimus

import redis.clients.jedis.DefaultJedisClientConfig
import redis.clients.jedis.DefaultJedisSocketFactory
import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import redis.clients.jedis.JedisClientConfig
import redis.clients.jedis.SslOptions
import java.io.ByteArrayOutputStream
import java.net.Socket
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * Where a Redis is and how to log in: parsed from `redis://[user[:password]@]host[:port][/db]`
 * or `rediss://...` (TLS). A Redis Cluster's URL (`redis-cluster://`) is read by
 * [RedisClusterEndpoint], with the same rules for the login part.
 *
 * The password is secret everywhere: [toString] shows `***`, and no message or cause of a parse
 * error holds any part of it. The URL is read by hand rather than by [java.net.URI], whose errors
 * quote the whole input; the user information ends at the last `@`, so a password may hold `/`,
 * `@`, spaces and `%` (a `%` followed by two hex digits is an escape, any other `%` is itself).
 */
internal class RedisEndpoint private constructor(
    val host: String,
    val port: Int,
    override val user: String?,
    /** The password; never put it in a message. */
    val password: String?,
    val database: Int,
    val tls: Boolean,
) : RedisTarget {
    /**
     * Opens a new connection. [timeout] bounds connecting, logging in and every command;
     * [blockingTimeout] bounds how long a blocking command may keep the socket silent before the
     * connection counts as dead (a half-open connection would otherwise block forever); it must
     * exceed the longest server-side wait the caller asks for. Errors are Jedis's, which never
     * hold the password.
     */
    override fun connect(clientName: String, timeout: Duration, blockingTimeout: Duration, onSocket: (Socket) -> Unit): Jedis =
        open(HostAndPort(host, port), clientConfig(user, password, tls, database, clientName, timeout, blockingTimeout), onSocket)

    override fun toString(): String {
        val login = when {
            user != null && password != null -> "$user:***@"
            user != null -> "$user@"
            password != null -> ":***@"
            else -> ""
        }
        val shownHost = if (':' in host) "[$host]" else host
        return "${if (tls) "rediss" else "redis"}://$login$shownHost:$port/$database"
    }

    companion object {
        internal const val DEFAULT_PORT = 6379
        private const val FORM = "expected redis://[user[:password]@]host[:port][/database] or rediss://... for TLS " +
            "(a Redis Cluster: redis-cluster://[user[:password]@]host:port[,host:port...], or rediss-cluster://...)"
        private val HOST_NAME = Regex("[A-Za-z0-9._-]+")
        private val IPV6 = Regex("[0-9A-Fa-f:.]+(%[A-Za-z0-9._-]+)?")

        fun parse(url: String): RedisEndpoint {
            val schemeEnd = url.indexOf("://")
            if (schemeEnd < 0) throw IllegalArgumentException("Redis URL '${redact(url)}' has no scheme; $FORM")
            val tls = when (val scheme = url.substring(0, schemeEnd).lowercase()) {
                "redis" -> false
                "rediss" -> true
                else -> throw IllegalArgumentException("Redis URL '${redact(url)}' has scheme '${shown(scheme)}'; $FORM")
            }
            val rest = url.substring(schemeEnd + 3)
            val at = rest.lastIndexOf('@')
            val (user, password) = if (at >= 0) login(rest.substring(0, at)) else null to null
            val location = rest.substring(at + 1) // host[:port][/database], nothing secret
            if (location.any { it == '?' || it == '#' }) {
                throw IllegalArgumentException("Redis URL '${redact(url)}' has a query or fragment, which Optimus does not read; $FORM")
            }
            val slash = location.indexOf('/')
            val authority = if (slash < 0) location else location.substring(0, slash)
            val path = if (slash < 0) "" else location.substring(slash + 1)
            val address = hostAndPort(url, authority)
            val database = if (path.isEmpty()) 0 else path.toIntOrNull()?.takeIf { it >= 0 }
                ?: throw IllegalArgumentException(
                    "Redis URL '${redact(url)}' has database '$path'; the database is a number (0 if omitted)",
                )
            return RedisEndpoint(address.host, address.port, user, password, database, tls)
        }

        /** The settings of one connection: login, TLS, database, and [timeout] for connecting and every reply. */
        fun clientConfig(
            user: String?,
            password: String?,
            tls: Boolean,
            database: Int,
            clientName: String,
            timeout: Duration,
            blockingTimeout: Duration,
        ): JedisClientConfig {
            val millis = timeout.toMillis().coerceIn(1, Int.MAX_VALUE.toLong()).toInt()
            val config = DefaultJedisClientConfig.builder()
                .resp2()
                .autoNegotiateProtocol(false)
                .connectionTimeoutMillis(millis)
                .socketTimeoutMillis(millis)
                .blockingSocketTimeoutMillis(blockingTimeout.toMillis().coerceIn(1, Int.MAX_VALUE.toLong()).toInt())
                .database(database)
                .clientName(clientName)
            // TLS with the JVM's trust store and full verification (SslOptions.defaults())
            if (tls) config.sslOptions(SslOptions.defaults())
            if (user != null) config.user(user)
            if (password != null) config.password(password)
            return config.build()
        }

        /**
         * A connection to [address], connected (errors are Jedis's, which never hold the password).
         * Its socket is opened once ([OneSocket]): a closed connection fails, never reconnects.
         * [onSocket] gets the socket before the login ([RedisTarget.connect]).
         */
        fun open(address: HostAndPort, config: JedisClientConfig, onSocket: (Socket) -> Unit = {}): Jedis {
            val jedis = Jedis(OneSocket(DefaultJedisSocketFactory(address, config), onSocket), config)
            try {
                jedis.connect()
            } catch (e: RuntimeException) {
                jedis.close()
                throw e
            }
            return jedis
        }

        /** The user and password of a URL's user information ([info]: everything before the last `@`). */
        fun login(info: String): Pair<String?, String?> {
            val colon = info.indexOf(':')
            val user = decode(if (colon < 0) info else info.substring(0, colon)).ifEmpty { null }
            return user to if (colon >= 0) decode(info.substring(colon + 1)) else null
        }

        /** A host and port of [authority] (`host[:port]` or `[ipv6][:port]`), checked; [url] only for messages. */
        fun hostAndPort(url: String, authority: String): HostAndPort {
            val (host, portText) = splitHostPort(url, authority)
            val port = if (portText == null) DEFAULT_PORT else portText.toIntOrNull()?.takeIf { it in 1..65535 }
                ?: throw IllegalArgumentException("Redis URL '${redact(url)}' has port '$portText'; the port is a number within 1..65535")
            return HostAndPort(host, port)
        }

        private fun splitHostPort(url: String, authority: String): Pair<String, String?> {
            if (authority.startsWith("[")) {
                val close = authority.indexOf(']')
                val host = if (close < 0) "" else authority.substring(1, close)
                val after = if (close < 0) "" else authority.substring(close + 1)
                if (!IPV6.matches(host) || (after.isNotEmpty() && !after.startsWith(":"))) {
                    throw IllegalArgumentException("Redis URL '${redact(url)}' has an invalid IPv6 host '$authority'; $FORM")
                }
                return host to after.removePrefix(":").takeIf { after.isNotEmpty() }
            }
            val colon = authority.lastIndexOf(':')
            val host = if (colon < 0) authority else authority.substring(0, colon)
            if (host.isEmpty()) throw IllegalArgumentException("Redis URL '${redact(url)}' names no host; $FORM")
            if (!HOST_NAME.matches(host)) {
                throw IllegalArgumentException(
                    "Redis URL '${redact(url)}' has an invalid host '$host' (letters, digits, '.', '-' and '_'; " +
                        "an IPv6 address goes in brackets); $FORM",
                )
            }
            return host to if (colon < 0) null else authority.substring(colon + 1)
        }

        /** Percent-decodes [part] as UTF-8; a `%` not followed by two hex digits stands for itself. */
        private fun decode(part: String): String {
            if ('%' !in part) return part
            val bytes = ByteArrayOutputStream(part.length)
            var i = 0
            while (i < part.length) {
                val c = part[i]
                if (c == '%' && i + 2 < part.length && isHex(part[i + 1]) && isHex(part[i + 2])) {
                    bytes.write(part.substring(i + 1, i + 3).toInt(16))
                    i += 3
                } else {
                    bytes.write(c.toString().toByteArray(UTF_8))
                    i++
                }
            }
            return bytes.toString(UTF_8)
        }

        private fun isHex(c: Char) = c in '0'..'9' || c in 'a'..'f' || c in 'A'..'F'

        /** At most 20 characters of a part that holds nothing secret, for messages. */
        private fun shown(part: String) = if (part.length <= 20) part else part.take(20) + "..."

        /**
         * The URL for messages: scheme, user and location; the password, whatever it holds, is
         * `***` (everything up to the last `@` is user information, as [parse] reads it).
         */
        fun redact(url: String): String {
            val schemeEnd = url.indexOf("://")
            val at = url.lastIndexOf('@')
            if (at < 0) return url
            if (schemeEnd < 0 || at < schemeEnd) return "***@" + url.substring(at + 1)
            val info = url.substring(schemeEnd + 3, at)
            val colon = info.indexOf(':')
            val login = if (colon < 0) info else info.substring(0, colon) + ":***"
            return url.substring(0, schemeEnd + 3) + login + url.substring(at)
        }
    }
}
