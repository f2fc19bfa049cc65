package dev.prime.optimus

import redis.clients.jedis.DefaultJedisClientConfig
import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import redis.clients.jedis.SslOptions
import java.net.URI
import java.net.URISyntaxException
import java.net.URLDecoder
import java.nio.charset.StandardCharsets
import java.time.Duration

/**
 * Where a Redis is and how to log in: parsed from `redis://[user[:password]@]host[:port][/db]`
 * or `rediss://...` (TLS). [toString] never shows the password.
 */
internal class RedisEndpoint private constructor(
    val host: String,
    val port: Int,
    val user: String?,
    private val password: String?,
    val database: Int,
    val tls: Boolean,
) {
    /**
     * Opens a new connection. [blockingTimeout] bounds how long a blocking command may keep the
     * socket silent before the connection counts as dead (a half-open connection would otherwise
     * block forever); it must exceed the longest server-side wait the caller asks for.
     */
    fun connect(clientName: String, timeout: Duration, blockingTimeout: Duration): Jedis {
        val config = DefaultJedisClientConfig.builder()
            .resp2()
            .autoNegotiateProtocol(false)
            .connectionTimeoutMillis(timeout.toMillis().toInt())
            .socketTimeoutMillis(timeout.toMillis().toInt())
            .blockingSocketTimeoutMillis(blockingTimeout.toMillis().toInt())
            .database(database)
            .clientName(clientName)
        // TLS with the JVM's trust store and full verification (SslOptions.defaults())
        if (tls) config.sslOptions(SslOptions.defaults())
        if (user != null) config.user(user)
        if (password != null) config.password(password)
        val jedis = Jedis(HostAndPort(host, port), config.build())
        try {
            jedis.connect()
        } catch (e: RuntimeException) {
            jedis.close()
            throw e
        }
        return jedis
    }

    override fun toString(): String {
        val login = when {
            user != null && password != null -> "$user:***@"
            user != null -> "$user@"
            password != null -> ":***@"
            else -> ""
        }
        return "${if (tls) "rediss" else "redis"}://$login$host:$port/$database"
    }

    companion object {
        private const val DEFAULT_PORT = 6379
        private const val FORM = "expected redis://[user[:password]@]host[:port][/database] or rediss://... for TLS"

        fun parse(url: String): RedisEndpoint {
            val uri = try {
                URI(url)
            } catch (e: URISyntaxException) {
                throw IllegalArgumentException("invalid Redis URL '${redact(url)}': ${e.reason}; $FORM", e)
            }
            val tls = when (uri.scheme?.lowercase()) {
                "redis" -> false
                "rediss" -> true
                else -> throw IllegalArgumentException("Redis URL '${redact(url)}' has scheme '${uri.scheme}'; $FORM")
            }
            val host = uri.host ?: throw IllegalArgumentException("Redis URL '${redact(url)}' names no host; $FORM")
            val port = if (uri.port == -1) DEFAULT_PORT else uri.port
            var user: String? = null
            var password: String? = null
            uri.rawUserInfo?.let { info ->
                val colon = info.indexOf(':')
                val rawUser = if (colon < 0) info else info.substring(0, colon)
                user = decode(rawUser).ifEmpty { null }
                if (colon >= 0) password = decode(info.substring(colon + 1))
            }
            val path = uri.path.orEmpty().removePrefix("/")
            val database = if (path.isEmpty()) 0 else path.toIntOrNull()?.takeIf { it >= 0 }
                ?: throw IllegalArgumentException(
                    "Redis URL '${redact(url)}' has database '$path'; the database is a number (0 if omitted)",
                )
            if (uri.rawQuery != null || uri.rawFragment != null) {
                throw IllegalArgumentException("Redis URL '${redact(url)}' has a query or fragment, which Optimus does not read; $FORM")
            }
            return RedisEndpoint(host, port, user, password, database, tls)
        }

        private fun decode(part: String) = URLDecoder.decode(part.replace("+", "%2B"), StandardCharsets.UTF_8)

        /** The URL with any password replaced by `***`, for messages. */
        fun redact(url: String): String = url.replace(Regex("(://[^:/@]*:)[^@/]*@"), "$1***@")
    }
}
