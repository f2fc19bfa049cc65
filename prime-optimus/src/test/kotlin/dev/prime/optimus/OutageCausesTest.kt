package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.exceptions.JedisDataException

class OutageCausesTest {

    /** One line per cause an outage meets, however often each repeats; a new outage starts afresh. */
    @Test
    fun anOutageLogsEachCauseOnce() {
        val outage = OutageCauses()
        val full = TooManyClients("redis://127.0.0.1:6379/0", JedisDataException("ERR max number of clients reached"))
        val attempts = listOf(
            JedisConnectionException("Unexpected end of stream."), full, full, JedisConnectionException("Connection refused"),
            JedisDataException("OOM command not allowed when used memory > 'maxmemory'."), full,
            JedisDataException("OOM command not allowed"), IllegalStateException("odd"),
        )
        assertEquals(listOf(true, true, false, false, true, false, false, true), attempts.map { outage.isNew(it) })
        assertEquals(true, outage.end())
        assertEquals(false, outage.end(), "no outage after a success")
        assertEquals(true, outage.isNew(full), "the next outage logs its causes again")
    }
}
